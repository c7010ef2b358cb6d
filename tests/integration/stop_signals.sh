# SIGTERM and SIGINT end every source this machine can start within 1 s: `record` with the simulated
# rig unpaced (a source that always has more) and paced, the kernel-log source following a file that
# keeps growing and reading /dev/kmsg (where it can be opened), and the agent. Each exits 0, and the
# store holds a closed session whose events are the ones the summary reports.
# (The GPIO source needs a GPIO chip: its in-process twin is tested in tests/unit/capture/stop_test.cpp.)
source "$(dirname "$0")/lib.bash"
CLEANUP_SIGNAL=KILL

# sessions STORE: "<sessions> <open sessions> <events>" of a store, read while it may be written.
sessions() {
  $PY - "$1" <<'EOF'
import sqlite3, sys
db = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True, timeout=5)
try:
    s, o = db.execute("SELECT count(*), count(*) - count(end_ns) FROM sessions").fetchone()
    e = db.execute("SELECT count(*) FROM events").fetchone()[0]
except sqlite3.OperationalError:  # not created yet
    s, o, e = 0, 0, 0
print(s, o, e)
EOF
}

# run_and_stop NAME SIGNAL MIN_EVENTS COMMAND...: starts COMMAND (its store is NAME.db), waits until
# its session is open with at least MIN_EVENTS events, sends SIGNAL and checks it exits 0 within 1 s
# with every session closed.
run_and_stop() {
  local name=$1 signal=$2 min_events=$3; shift 3
  "$@" > "$name.out" 2> "$name.err" &
  local pid=$!
  PIDS+=("$pid")
  local state="0 0 0"
  for _ in $(seq 200); do
    kill -0 "$pid" 2>/dev/null || { cat "$name.err" >&2; fail "$name exited before the signal"; }
    [ -f "$name.db" ] && state=$(sessions "$name.db")
    read -r s o e <<< "$state"
    [ "$o" -ge 1 ] && [ "$e" -ge "$min_events" ] && break
    sleep 0.05
  done
  read -r s o e <<< "$state"
  [ "$o" -ge 1 ] && [ "$e" -ge "$min_events" ] || fail "$name: no open session with $min_events events (have $state)"
  local start end rc=0
  start=$(date +%s%N)
  kill "-$signal" "$pid"
  # Give it 5 s at most (a source that ignores the stop would keep the test waiting forever).
  for _ in $(seq 500); do kill -0 "$pid" 2>/dev/null || break; sleep 0.01; done
  end=$(date +%s%N)
  kill -0 "$pid" 2>/dev/null && fail "$name still runs 5 s after $signal"
  wait "$pid" || rc=$?
  local ms=$(( (end - start) / 1000000 ))
  [ "$rc" = 0 ] || { cat "$name.err" >&2; fail "$name exited $rc after $signal"; }
  [ "$ms" -lt 1000 ] || fail "$name took $ms ms to stop after $signal (limit 1000 ms)"
  read -r s o e <<< "$(sessions "$name.db")"
  [ "$s" -ge 1 ] && [ "$o" = 0 ] || fail "$name: sessions $s, still open $o after $signal"
  echo "$name: stopped by $signal in $ms ms, $e events stored"
}

SIM=(--node vehicle --role effect --source sim --sim-set manoeuvres=1000000000)

# The unpaced simulation always has events ready: the stop must not wait for it to run dry.
run_and_stop sim_unpaced TERM 10000 "$M2MLAT" record --store sim_unpaced.db "${SIM[@]}" --quiet --json
$PY - sim_unpaced <<'EOF'
import json, sqlite3, sys
name = sys.argv[1]
summary = json.load(open(f"{name}.out"))
assert summary["stop_reason"] == "SIGTERM", summary["stop_reason"]
db = sqlite3.connect(f"{name}.db")
stored = db.execute("SELECT count(*) FROM events").fetchone()[0]
assert stored == summary["events"], (stored, summary["events"])
EOF
run_and_stop sim_unpaced_int INT 10000 "$M2MLAT" record --store sim_unpaced_int.db "${SIM[@]}" --quiet
grep -q "stopped by SIGINT" sim_unpaced_int.out || fail "sim_unpaced_int: $(cat sim_unpaced_int.out)"

run_and_stop sim_paced TERM 1 "$M2MLAT" record --store sim_paced.db "${SIM[@]}" --sim-paced --quiet \
  --sim-set motion.interval_min=150ms --sim-set motion.interval_max=300ms --sim-set motion.min_pause=20ms

# A followed kernel log that another program keeps appending to, one GPIO line a millisecond.
: > follow.log
$PY - follow.log <<'EOF' &
import sys, time
ns = 1_700_000_000_000_000_000
with open(sys.argv[1], "a", buffering=1) as log:
    while True:
        ns += 1_000_000
        log.write(f"[ 1.0] GPIO_16_IRQ:{ns}\n")
        time.sleep(0.001)
EOF
PIDS+=("$!")
run_and_stop kmsg_file TERM 10 "$M2MLAT" record --store kmsg_file.db --node vehicle --source kmsg \
  --kmsg follow.log --no-clock-monitor --quiet

# The kernel's log device, where this user may read it (root, or kernel.dmesg_restrict=0): no GPIO
# lines come, so the source is idle when the signal arrives.
if $PY -c 'import os; os.close(os.open("/dev/kmsg", os.O_RDONLY | os.O_NONBLOCK))' 2> /dev/null; then
  run_and_stop kmsg_device TERM 0 "$M2MLAT" record --store kmsg_device.db --node vehicle --source kmsg \
    --no-clock-monitor --quiet
else
  echo "kmsg_device: /dev/kmsg cannot be read by this user: not tested"
fi

# The agent (paced simulation, HTTP server) ends within the same second.
run_and_stop agent TERM 1 "$M2MLAT" agent --store agent.db --node vehicle --role effect --source sim \
  --listen 127.0.0.1:0 --quiet --commit-interval 20ms \
  --sim-set motion.interval_min=150ms --sim-set motion.interval_max=300ms --sim-set motion.min_pause=20ms
echo "1 passed, 0 failed"
