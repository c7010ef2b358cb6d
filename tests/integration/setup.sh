#!/usr/bin/env bash
# `m2mlat setup gpio|irq|pin-chrony|agent|board` into a temporary root (--root): the dry run prints
# every change and makes none; the real run writes exactly what was announced (the udev rule equal to
# the package's, chrony.conf accepted by chronyd, an agent configuration that `m2mlat record` and
# `m2mlat agent` run with, the env file the unit reads, the IRQ affinity in a fake /proc); a second
# run changes nothing; a changed option shows a diff and keeps a backup; bad input changes nothing.
source "$(dirname "$0")/lib.bash"
PACKAGING=$(realpath "$DATA/../../packaging")
R=$WORK/root
mkdir -p "$R/etc" "$R/proc/irq/183"
printf 'root:x:0:\ngpio:x:997:\n' >"$R/etc/group"
printf '0-3\n' >"$R/proc/irq/183/smp_affinity_list"
cat >"$R/proc/interrupts" <<'IRQ'
           CPU0       CPU1       CPU2       CPU3
183:         12          0          0          0  pinctrl-rp1  16 Edge      m2mlat-wheel
IPI0:       100        100        100        100       Rescheduling interrupts
IRQ

board() {
  "$M2MLAT" setup board --role vehicle --node vehicle --chip pinctrl-rp1 --line GPIO16 --mode co-referenced \
    --reference 10.0.0.1 --listen 10.0.0.2:8470 --token-file /etc/m2mlat/token --irq-core 2 --chrony-core 1 \
    --user pi --root "$R" "$@"
}

# 1. Dry run: every file with its content, every command, nothing written.
board --dry-run >dry.txt || fail "dry run: $(cat dry.txt)"
for want in "would write $R/etc/udev/rules.d/60-m2mlat-gpio.rules" "would write $R/etc/chrony/chrony.conf" \
  "would write $R/etc/m2mlat/vehicle.toml" "would write $R/etc/m2mlat/vehicle.env" \
  "would write $R/proc/irq/183/smp_affinity_list" "| server 10.0.0.1 minpoll 2 maxpoll 2 iburst prefer" \
  "| CPUAffinity=1" "| M2MLAT_IRQ_CPU=2" "would run: usermod -aG gpio pi" "would run: systemctl restart chrony" \
  "start it: systemctl enable --now m2mlat-agent@vehicle" "none made"; do
  grep -qF -- "$want" dry.txt || { cat dry.txt >&2; fail "dry run does not show '$want'"; }
done
[ "$(grep -c 'would run: systemctl restart chrony' dry.txt)" = 1 ] || fail "chrony restarted twice"
[ ! -e "$R/etc/m2mlat" ] && [ ! -e "$R/etc/udev" ] || fail "the dry run wrote files"
[ "$(cat "$R/proc/irq/183/smp_affinity_list")" = 0-3 ] || fail "the dry run routed the IRQ"

# 2. The real run writes what the dry run showed; commands are not run under --root.
board >run.txt || fail "setup board: $(cat run.txt)"
grep -qF "not run under --root $R: usermod -aG gpio pi" run.txt || fail "commands: $(cat run.txt)"
cmp -s "$R/etc/udev/rules.d/60-m2mlat-gpio.rules" "$PACKAGING/60-m2mlat-gpio.rules" ||
  fail "the udev rule differs from the package's"
[ "$(cat "$R/proc/irq/183/smp_affinity_list")" = 2 ] || fail "IRQ 183 not routed to CPU 2"
grep -qx 'M2MLAT_LISTEN=10.0.0.2:8470' "$R/etc/m2mlat/vehicle.env" &&
  grep -qx 'M2MLAT_AGENT_ARGS="--token-file /etc/m2mlat/token"' "$R/etc/m2mlat/vehicle.env" &&
  grep -qx 'M2MLAT_IRQ_NAME=m2mlat-wheel' "$R/etc/m2mlat/vehicle.env" || fail "env: $(cat "$R/etc/m2mlat/vehicle.env")"
if command -v chronyd >/dev/null; then
  chronyd -p -f "$R/etc/chrony/chrony.conf" >/dev/null 2>chrony.err || fail "chronyd refuses: $(cat chrony.err)"
fi
# The packaged irq helper finds the same IRQ by the name setup wrote.
( set -a; source "$R/etc/m2mlat/vehicle.env"; printf '0-3\n' >"$R/proc/irq/183/smp_affinity_list"
  M2MLAT_PROC=$R/proc M2MLAT_IRQ_WAIT=1 sh "$PACKAGING/irq-affinity" ) >helper.txt 2>&1 || fail "irq-affinity: $(cat helper.txt)"
grep -q 'IRQ 183 (m2mlat-wheel) routed to CPU 2' helper.txt || fail "irq-affinity: $(cat helper.txt)"

# The agent's configuration runs: record (sim source in place of the sensor) and the agent.
"$M2MLAT" record --config "$R/etc/m2mlat/vehicle.toml" --source sim --store rec.db --count 5 --quiet >rec.txt ||
  fail "record with the written configuration"
grep -q 'node vehicle (effect), 5 events' rec.txt || fail "record: $(cat rec.txt)"
"$M2MLAT" agent --config "$R/etc/m2mlat/vehicle.toml" --source sim --store agent.db --listen 127.0.0.1:0 \
  --count 3 --quiet >agent.txt 2>&1 || fail "agent with the written configuration: $(cat agent.txt)"
grep -q '^listening 127.0.0.1:' agent.txt || fail "agent: $(cat agent.txt)"

# 3. Idempotent: the same run again changes nothing and says so (with pi now in the group, as the
# usermod that is not run under --root would have done).
printf 'root:x:0:\ngpio:x:997:pi\n' >"$R/etc/group"
board >again.txt || fail "second run"
grep -q 'nothing to change' again.txt && ! grep -qE 'writing|running|not run' again.txt ||
  { cat again.txt >&2; fail "the second run changed something"; }

# 4. One option changed: its file's diff, a backup, the rest unchanged.
"$M2MLAT" setup agent --role vehicle --node vehicle --chip pinctrl-rp1 --line GPIO17 --root "$R" >change.txt ||
  fail "setup agent: $(cat change.txt)"
grep -qx -- '    -line = "GPIO16"' change.txt && grep -qx -- '    +line = "GPIO17"' change.txt ||
  { cat change.txt >&2; fail "no diff shown"; }
grep -q 'line = "GPIO16"' "$R/etc/m2mlat/vehicle.toml.m2mlat-backup" || fail "no backup"
grep -q 'M2MLAT_IRQ_CPU=2' "$R/etc/m2mlat/vehicle.env" || fail "setup agent dropped the IRQ keys"

# 5. The single parts.
"$M2MLAT" setup gpio --user pi --user alice --root "$R" >gpio.txt || fail "setup gpio"
grep -q 'usermod -aG gpio alice' gpio.txt && ! grep -q 'gpio pi' gpio.txt && grep -q 'unchanged' gpio.txt ||
  fail "setup gpio: $(cat gpio.txt)"
"$M2MLAT" setup gpio --user pi --root "$R" | grep -q 'nothing to change' || fail "setup gpio with pi in gpio"
"$M2MLAT" setup pin-chrony --core 1 --root "$R" | grep -q 'nothing to change' || fail "setup pin-chrony"
"$M2MLAT" setup irq --chip pinctrl-rp1 --line GPIO16 --core 3 --root "$R" >irq.txt || fail "setup irq"
grep -q 'was: 2' irq.txt && grep -q 'lasts until' irq.txt || fail "setup irq: $(cat irq.txt)"
[ "$(cat "$R/proc/irq/183/smp_affinity_list")" = 3 ] || fail "setup irq did not route"
"$M2MLAT" setup irq --chip pinctrl-rp1 --line GPIO5 --channel other --core 3 --node operator --root "$R" >irq2.txt ||
  fail "setup irq, line not held"
grep -q "no interrupt named 'm2mlat-other'" irq2.txt && grep -qx 'M2MLAT_IRQ_CPU=3' "$R/etc/m2mlat/operator.env" ||
  fail "setup irq --node: $(cat irq2.txt)"
"$M2MLAT" setup chrony --mode autonomous >/dev/null || fail "setup chrony still works"

# 6. Bad input: a usage error (exit 2), nothing written.
before=$(find "$R" -type f | sort | xargs md5sum)
expect_exit 2 "$M2MLAT" setup agent --role driver --node vehicle --chip c --line 1 --root "$R"
grep -q "operator" err.txt || fail "bad role: $(cat err.txt)"
expect_exit 2 "$M2MLAT" setup agent --role vehicle --node ../etc/passwd --chip c --line 1 --root "$R"
expect_exit 2 "$M2MLAT" setup agent --role vehicle --node v --chip c --line 1 --listen 0.0.0.0:8470 --root "$R"
grep -q 'token-file' err.txt || fail "listen without token: $(cat err.txt)"
expect_exit 2 "$M2MLAT" setup board --role vehicle --node v --chip c --line 1 --mode co-referenced --root "$R"
grep -q 'reference' err.txt || fail "peer without reference: $(cat err.txt)"
[ "$(find "$R" -type f | sort | xargs md5sum)" = "$before" ] || fail "bad input changed files"
echo "ok: setup dry run, run, idempotence, diff and backup, single parts, bad input"
