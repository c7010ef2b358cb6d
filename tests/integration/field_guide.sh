#!/usr/bin/env bash
# Every command of docs/field-guide.md, run in order: the ```sh blocks are extracted, and each line
# is run in a temporary folder, with one temporary root folder per board and the simulated rig
# standing in for the sensors. The comment "# field-guide: MARK" at the end of a line says what
# stands in for the board (the guide's last section lists the marks):
#   (none)       run as written
#   root         `m2mlat setup <part>` gets --root (its options as written); other commands (setup
#                chrony --output, the token) get their /etc/... paths under the board's root
#   service      `systemctl enable --now|stop m2mlat-agent@NODE`: setup must have printed the enable
#                line; the agent is started as the unit would (NODE.toml, NODE.env) with --source sim
#                on a loopback port, or stopped
#   sim          record: --source sim; board addresses -> the stand-in agents' ports; --duration 5s
#   hardware     real GPIO: its options are checked against `--help`; a simulated pulse recording is
#                imported in place of its --store
#   board-state  reads this machine's state: exit 0 (all fine) or 1 (something to fix) accepted
#   copy, fetch  scp between the boards: a copy between the board roots / the file must be here
# The first line of a block, "# on the operator board" (vehicle, each, coordinator), picks the root;
# "each" and the coordinator use the operator's. A board root starts as the package leaves it
# (/etc/m2mlat exists) with /etc/group holding gpio (as on Raspberry Pi OS). Finally the results are checked: the roots' files, the campaign's three
# scenarios, the synctest, the report.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"  # process cleanup (AGENT_PIDS), wait_for_line
GUIDE=$(realpath "$DATA/../../docs/field-guide.md")
MAGNETS=magnets_deg=0,20,40,60,80,100,120,140,160  # the guide's nine magnets 20 degrees apart
for b in operator vehicle; do
  mkdir -p "$WORK/$b-root/etc/m2mlat"  # the package is installed (it ships /etc/m2mlat/agent.toml.example)
  printf 'root:x:0:\ngpio:x:997:\n' >"$WORK/$b-root/etc/group"
done
declare -A PORT PID
: >all-output.txt

# Extract: one line per command, BOARD, MARK and COMMAND separated by \x1f (continuation lines joined).
$PY - "$GUIDE" >commands.txt <<'PY'
import re, sys
board, block, pending = None, False, ""
for raw in open(sys.argv[1], encoding="utf-8"):
    line = raw.rstrip("\n")
    if line.startswith("```"):
        block = line.strip() == "```sh" if not block else False
        board = None
        continue
    if not block:
        continue
    m = re.match(r"# on (?:the )?(operator|vehicle|each|coordinator)\b", line)
    if m and board is None:
        board = m.group(1)
        continue
    if board is None:
        sys.exit(f"field guide: a sh block without '# on the ... board' first: {line}")
    if line.endswith("\\"):
        pending += line[:-1]
        continue
    line, pending = pending + line, ""
    if not line.strip() or line.lstrip().startswith("#"):
        continue
    mark = ""
    m = re.search(r"\s+# field-guide: ([a-z-]+)\s*$", line)
    if m:
        mark, line = m.group(1), line[: m.start()]
    print(f"{board}\x1f{mark}\x1f{line.strip()}")  # not a tab: bash read would merge empty fields
PY
[ "$(wc -l <commands.txt)" -ge 25 ] || fail "only $(wc -l <commands.txt) commands found in the guide"

root_of() { case $1 in vehicle) echo "$WORK/vehicle-root" ;; *) echo "$WORK/operator-root" ;; esac; }
board_of_ip() { case $1 in 10.0.0.1) echo operator ;; 10.0.0.2) echo vehicle ;; *) fail "unknown board $1" ;; esac; }

# run_line CMD: runs it with bash in $WORK, m2mlat meaning the tested executable; output kept.
run_line() {
  local cmd=$1 rc=0
  M2MLAT_BIN=$M2MLAT bash -c "m2mlat() { \"\$M2MLAT_BIN\" \"\$@\"; }; $cmd" >line.out 2>&1 || rc=$?
  cat line.out >>all-output.txt
  return $rc
}

# A simulated recording of the pulse line (500 ms, 1200 edges) for NODE, imported into STORE: the
# same true edges on both boards, the vehicle 40 us late with 5 us of noise.
pulse_stand_in() {
  local node=$1 store=$2
  $PY - "$node" >"$node-pulse.csv" <<'PY'
import sys, random
node = sys.argv[1]
rng = random.Random(11 if node == "operator" else 12)
t0 = 1_780_304_400_000_000_000
print("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags")
for k in range(1200):
    t = t0 + k * 500_000_000 + (0 if node == "operator" else 40_000 + int(rng.gauss(0, 5_000)))
    print(f"{node},pulse,{'rising' if k % 2 == 0 else 'falling'},realtime,{t},{k + 1},{k + 1},0")
PY
  "$M2MLAT" import "$node-pulse.csv" --store "$store" --role observer --scenario sync >/dev/null
}

start_stand_in_agent() {
  local node=$1 root=$2 args
  [ -f "$root/etc/m2mlat/$node.toml" ] || fail "service $node: setup wrote no $root/etc/m2mlat/$node.toml"
  grep -qF "systemctl enable --now m2mlat-agent@$node" all-output.txt || fail "setup did not print the enable line for $node"
  # As the unit: its env file, then `m2mlat agent --config ... $M2MLAT_AGENT_ARGS` (here on loopback).
  args=$(set -a; [ -f "$root/etc/m2mlat/$node.env" ] && source "$root/etc/m2mlat/$node.env"; echo "${M2MLAT_AGENT_ARGS:-}")
  args=${args//\/etc\//$root/etc/}
  : >"$node-agent.log"
  # shellcheck disable=SC2086
  "$M2MLAT" agent --config "$root/etc/m2mlat/$node.toml" --store "$node-agent.db" --listen 127.0.0.1:0 $args \
    --source sim --seed 7 --sim-set "$MAGNETS" >>"$node-agent.log" 2>&1 &
  PID[$node]=$!
  AGENT_PIDS+=("${PID[$node]}")
  PORT[$node]=$(wait_for_line "$node-agent.log" 'listening 127\.0\.0\.1:[0-9]+' | sed 's/.*://')
}

n=0
while IFS=$'\x1f' read -r board mark cmd; do
  n=$((n + 1))
  root=$(root_of "$board")
  mapped=${cmd//\/etc\//$root/etc/}
  case $mark in
    "")
      run_line "$cmd" || { cat line.out >&2; fail "guide command failed: $cmd"; } ;;
    root)
      # setup writes the target's paths into its files: its options stay as written, --root moves the files.
      if [[ $cmd =~ ^m2mlat\ setup\ ([a-z-]+) ]] && [ "${BASH_REMATCH[1]}" != chrony ]; then mapped="$cmd --root $root"; fi
      mapped=${mapped//chgrp m2mlat/chgrp $(id -gn)}
      run_line "$mapped" || { cat line.out >&2; fail "guide command failed: $cmd"; }
      if [[ $cmd =~ ^m2mlat\ setup\ board ]] && [[ $cmd != *--dry-run* ]]; then  # "run it again: nothing to change"
        run_line "$mapped" && grep -q 'nothing to change' line.out || { cat line.out >&2; fail "second run changed something: $cmd"; }
      fi ;;
    copy)
      [[ $cmd =~ ^scp\ ([^ ]+)\ root@([0-9.]+):([^ ]+)$ ]] || fail "copy: cannot read '$cmd'"
      to=$(root_of "$(board_of_ip "${BASH_REMATCH[2]}")")
      cp "$root${BASH_REMATCH[1]}" "$to${BASH_REMATCH[3]}" || fail "copy: $cmd" ;;
    fetch)
      [[ $cmd =~ ^scp\ root@[0-9.]+:([^ ]+)\ \.$ ]] || fail "fetch: cannot read '$cmd'"
      [ -s "${BASH_REMATCH[1]}" ] || fail "fetch: ${BASH_REMATCH[1]} was not made by the steps before" ;;
    service)
      [[ $cmd =~ ^systemctl\ (enable\ --now|stop)\ m2mlat-agent@([A-Za-z0-9_.-]+)$ ]] || fail "service: cannot read '$cmd'"
      node=${BASH_REMATCH[2]}
      if [ "${BASH_REMATCH[1]}" = stop ]; then
        [ -n "${PID[$node]:-}" ] || fail "service: $node was not started"
        kill -TERM "${PID[$node]}" && wait "${PID[$node]}" || fail "the $node agent did not stop cleanly"
        grep -q 'stopped by SIGTERM' "$node-agent.log" || fail "agent $node: $(cat "$node-agent.log")"
        PID[$node]=
      else
        start_stand_in_agent "$node" "$root"
      fi ;;
    sim)
      for b in operator vehicle; do
        ip=10.0.0.$([ $b = operator ] && echo 1 || echo 2)
        [ -n "${PORT[$b]:-}" ] && mapped=${mapped//http:\/\/$ip:8470/http:\/\/127.0.0.1:${PORT[$b]}}
      done
      mapped=$(sed -E 's/--duration [0-9a-z]+/--duration 5s/' <<<"$mapped")
      [[ $cmd =~ ^m2mlat\ record ]] && mapped+=" --source sim --seed 7 --sim-set $MAGNETS --quiet"
      [[ $mapped == *10.0.0.* ]] && fail "sim: a board address is left in '$mapped'"
      run_line "$mapped" || { cat line.out >&2; fail "guide command failed (simulated): $cmd"; } ;;
    hardware)
      read -r -a words <<<"$cmd"
      [ "${words[0]}" = m2mlat ] || fail "hardware: not an m2mlat command: $cmd"
      "$M2MLAT" "${words[1]}" --help >help.txt || fail "hardware: m2mlat ${words[1]} --help"
      for w in "${words[@]}"; do
        if [[ $w == --* ]]; then grep -qE -- "(^| |,)$w( |=|$)" help.txt || fail "hardware: m2mlat ${words[1]} has no option $w"; fi
      done
      if [[ $cmd == *"--channel pulse="* ]]; then
        [[ $cmd =~ --node\ ([^ ]+) ]] && node=${BASH_REMATCH[1]}
        [[ $cmd =~ --store\ ([^ ]+) ]] && pulse_stand_in "$node" "${BASH_REMATCH[1]}"
      fi ;;
    board-state)
      rc=0; run_line "$cmd" || rc=$?
      [ "$rc" -le 1 ] || { cat line.out >&2; fail "'$cmd' exited $rc"; } ;;
    *) fail "unknown mark '$mark' in: $cmd" ;;
  esac
done <commands.txt

# What the guide says you should see.
for b in operator vehicle; do
  r=$WORK/$b-root
  for f in etc/udev/rules.d/60-m2mlat-gpio.rules etc/chrony/chrony.conf etc/m2mlat/$b.toml etc/m2mlat/$b.env \
    etc/systemd/system/chrony.service.d/m2mlat-cpu.conf; do
    [ -s "$r/$f" ] || fail "$b: no $f"
  done
done
grep -q '^server 10.0.0.1 ' "$WORK/vehicle-root/etc/chrony/chrony.conf" || fail "the vehicle does not follow the operator"
grep -q '^allow 10.0.0.0/24' "$WORK/operator-root/etc/chrony/chrony.conf" || fail "the operator does not serve"
cmp -s "$WORK/operator-root/etc/m2mlat/token" "$WORK/vehicle-root/etc/m2mlat/token" || fail "the token was not copied"
"$M2MLAT" stats campaign.db >stats.txt || fail "stats of the campaign"
for s in static_wifi static_5g dynamic; do grep -q "^$s " stats.txt || { cat stats.txt >&2; fail "no scenario $s"; }; done
$PY -c 'import json; d = json.load(open("sync.json")); print(d["format"] if "format" in d else "")' >/dev/null ||
  fail "sync.json is not JSON"
[ -s report/report.html ] || fail "no report/report.html"
grep -q 'E_calib\|calib' all-output.txt || fail "budget shows no calibration term"
echo "ok: $n commands of docs/field-guide.md run"
