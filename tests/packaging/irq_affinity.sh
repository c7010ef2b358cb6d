#!/usr/bin/env bash
# The unit's IRQ helper (packaging/irq-affinity) against a fake /proc: it routes the IRQs whose action
# is the configured name (the last column of /proc/interrupts, or one of a comma-separated list),
# and only those; does nothing without M2MLAT_IRQ_CPU; fails (for the journal) on a name that never
# appears, a bad CPU, or an unwritable affinity file.
set -euo pipefail
HELPER=$(cd "$(dirname "$0")/../.." && pwd)/packaging/irq-affinity
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
export M2MLAT_PROC=$WORK/proc M2MLAT_IRQ_WAIT=0
mkdir -p "$M2MLAT_PROC"
cat >"$M2MLAT_PROC/interrupts" <<'TXT'
           CPU0       CPU1       CPU2       CPU3
 11:          0          0          0          0     GICv2  30 Level     arch_timer
185:         12          0          0          0  pinctrl-rp1  16 Edge      m2mlat-wheel
186:          3          0          0          0  pinctrl-rp1  17 Edge      m2mlat-pulse, m2mlat-wheel
187:          0          0          0          0  pinctrl-rp1  18 Edge      other-driver
188:          0          0          0          0  pinctrl-rp1  19 Edge      m2mlat-wheel2
NMI:          0          0          0          0   Non-maskable interrupts
TXT
for irq in 11 185 186 187 188; do
  mkdir -p "$M2MLAT_PROC/irq/$irq"
  echo 0-3 >"$M2MLAT_PROC/irq/$irq/smp_affinity_list"
done
affinity() { cat "$M2MLAT_PROC/irq/$1/smp_affinity_list"; }

# Nothing configured: nothing done.
env -u M2MLAT_IRQ_CPU M2MLAT_IRQ_NAME=m2mlat-wheel "$HELPER" || fail "exit status without M2MLAT_IRQ_CPU"
[ "$(affinity 185)" = 0-3 ] || fail "wrote without M2MLAT_IRQ_CPU"

M2MLAT_IRQ_CPU=3 M2MLAT_IRQ_NAME=m2mlat-wheel "$HELPER" >"$WORK/out.txt" || fail "routing m2mlat-wheel"
[ "$(affinity 185)" = 3 ] && [ "$(affinity 186)" = 3 ] || fail "m2mlat-wheel's IRQs 185, 186 not routed"
for irq in 11 187 188; do [ "$(affinity $irq)" = 0-3 ] || fail "IRQ $irq routed though not named"; done
grep -q 'IRQ 186 (m2mlat-wheel) routed to CPU 3' "$WORK/out.txt" || fail "no report line: $(cat "$WORK/out.txt")"

# A name used as a word of the description (the trigger type) is not an action.
M2MLAT_IRQ_CPU=2 M2MLAT_IRQ_NAME=Edge "$HELPER" 2>/dev/null && fail "'Edge' matched a trigger type"
for irq in 11 185 186 187 188; do [ "$(affinity $irq)" != 2 ] || fail "IRQ $irq routed for 'Edge'"; done

# Several names; one missing: the others are routed, the exit status says so.
M2MLAT_IRQ_CPU=1 M2MLAT_IRQ_NAME="m2mlat-pulse m2mlat-absent" "$HELPER" 2>"$WORK/err.txt" &&
  fail "a missing name exited 0"
[ "$(affinity 186)" = 1 ] || fail "m2mlat-pulse not routed"
grep -q "no interrupt named 'm2mlat-absent'" "$WORK/err.txt" || fail "no message for the missing name"

M2MLAT_IRQ_CPU=x M2MLAT_IRQ_NAME=m2mlat-wheel "$HELPER" 2>/dev/null && fail "CPU 'x' accepted"
# An affinity file the helper cannot write (as root, a directory in its place).
rm "$M2MLAT_PROC/irq/188/smp_affinity_list"
mkdir "$M2MLAT_PROC/irq/188/smp_affinity_list"
M2MLAT_IRQ_CPU=1 M2MLAT_IRQ_NAME=m2mlat-wheel2 "$HELPER" 2>"$WORK/err.txt" && fail "an unwritable file exited 0"
grep -q 'could not route IRQ 188' "$WORK/err.txt" || fail "no message for the refused write"

# It waits for the name to appear (the agent requests its lines after the helper starts).
sed -i 's/m2mlat-wheel2/m2mlat-late/' "$M2MLAT_PROC/interrupts"
cp "$M2MLAT_PROC/interrupts" "$WORK/late"
sed -i '/m2mlat-late/d' "$M2MLAT_PROC/interrupts"
rmdir "$M2MLAT_PROC/irq/188/smp_affinity_list"
echo 0-3 >"$M2MLAT_PROC/irq/188/smp_affinity_list"
(sleep 0.5 && cp "$WORK/late" "$M2MLAT_PROC/interrupts") &
M2MLAT_IRQ_WAIT=5 M2MLAT_IRQ_CPU=2 M2MLAT_IRQ_NAME=m2mlat-late "$HELPER" >/dev/null || fail "did not wait for the name"
wait
[ "$(affinity 188)" = 2 ] || fail "the late IRQ not routed"
echo "irq_affinity: ok"
