# The live stage breakdown through real processes on loopback: two paced simulated agents (the same
# rig: operator = cause, vehicle = effect) with --mark-port, a stack's markers sent to both (a command
# marked `cmd` on the operator every 10 ms, `apply` on the vehicle 5 ms later), and `m2mlat collect
# --stages` with its dashboard. The live summary's `breakdown` (/api/live) must have complete chains
# and, once everything is collected, equal the breakdown member of `m2mlat stats --stages --json` on
# the campaign store, field for field (the same join on the same pairs and markers). A bad rule is a
# usage error before anything starts.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

printf '%s\n' 'to_command = first operator:cmd after cause' 'to_apply = same key vehicle:apply' \
  'actuator = effect' >stages.txt
printf 'to_command = first operator:cmd after the cause\nrest = effect\n' >bad-stages.txt

# The simulated rig starts now (true time = this host's CLOCK_REALTIME, as the marks' stamps are).
START=$(date +%s)
start_agent operator cause 11 operator.db 127.0.0.1:0 --sim-paced --sim-set "start=$START" --mark-port 0 \
  --commit-interval 50ms
OP=$AGENT_PORT
start_agent vehicle effect 11 vehicle.db 127.0.0.1:0 --sim-paced --sim-set "start=$START" --mark-port 0 \
  --commit-interval 50ms
VE=$AGENT_PORT
OP_MARKS=$(wait_for_line operator.log 'marks 127\.0\.0\.1:[0-9]+' | sed 's/.*://')
VE_MARKS=$(wait_for_line vehicle.log 'marks 127\.0\.0\.1:[0-9]+' | sed 's/.*://')
AGENTS=(--agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE")

expect_exit 2 "$M2MLAT" collect "${AGENTS[@]}" --store bad.db --stages bad-stages.txt --duration 1s
grep -q 'bad-stages.txt:1: selector' err.txt || fail "the bad rule's error names no file and line: $(cat err.txt)"
[ ! -e bad.db ] || fail "a bad rule still created the store"

"$M2MLAT" collect "${AGENTS[@]}" --store campaign.db --start-session --scenario live --label run-1 \
  --stages stages.txt --dashboard 127.0.0.1:0 --refresh 200ms --no-live --quiet >collect.out 2>collect.err &
COLLECT_PID=$!
URL=$(wait_for_line collect.err 'dashboard http://[0-9.:]+/' | sed 's/^dashboard //')
# The stack marks its commands until the live view has two complete chains. (The paced boards' first
# manoeuvre may fall before the session or the first marks, and which events get their marks depends
# on when the processes got the CPU: wait for the chains, not for a fixed time; 60 s is a safety net.)
"$PY" "$HERE/mark_sender.py" "$OP_MARKS" "$VE_MARKS" 60 >sender.out &
SENDER_PID=$!
AGENT_PIDS+=("$SENDER_PID")  # stopped with the boards if the test fails
complete=0
for ((i = 0; i < 300 && complete < 2; i++)); do
  sleep 0.2
  complete=$("$PY" -c 'import json, sys, urllib.request
b = json.load(urllib.request.urlopen(sys.argv[1] + "api/live", timeout=5))["summary"].get("breakdown") or {}
print(b.get("complete", 0))' "$URL")
done
[ "$complete" -ge 2 ] || fail "the live breakdown had $complete complete chains after 60 s"
kill -TERM "$SENDER_PID"
wait "$SENDER_PID"
unset 'AGENT_PIDS[-1]'

# The boards stop (nothing more to collect); the live figure must then reach the offline one.
for pid in "${AGENT_PIDS[@]}"; do kill -TERM "$pid"; wait "$pid" 2>/dev/null || true; done
AGENT_PIDS=()
started=$(date +%s%N)
for ((i = 0; i < 50; i++)); do
  "$M2MLAT" stats campaign.db --scenario live --stages stages.txt --bootstrap 0 --json >stats.json 2>stats.err ||
    { cat stats.err >&2; fail "stats --stages on the campaign failed"; }
  "$PY" - "$URL" stats.json >compare.txt <<'PY' && break
import json, sys, urllib.request
live = json.load(urllib.request.urlopen(sys.argv[1] + "api/live", timeout=5))["summary"]
offline = [s for s in json.load(open(sys.argv[2]))["scenarios"] if s["scenario"] == "live"][0]["breakdown"]
print(json.dumps({"live": live["breakdown"], "offline": offline}))
sys.exit(0 if live["breakdown"] == offline else 1)
PY
  sleep 0.2
done
"$PY" - compare.txt sender.out "$started" <<'PY'
import json, sys, time
d = json.load(open(sys.argv[1]))
live, offline = d["live"], d["offline"]
assert live == offline, "the live breakdown never reached the offline one:\n%s\n%s" % (live, offline)
assert [s["name"] for s in live["stages"]] == ["to_command", "to_apply", "actuator"], live
assert live["complete"] >= 2, live  # seen live before the boards stopped
assert live["complete"] + live["incomplete"] == live["events"], live
st = {s["name"]: s for s in live["stages"]}
# Marks every 10 ms: the first command follows the cause by 10 ms at most on the true time line; the
# simulated boards' clock errors and sensor latencies move the cause's stamp by tens of ms more.
# `apply` follows `cmd` by the sender's 5 ms sleep (a few ms more under load), both on this host's clock.
assert 0 <= st["to_command"]["max_ns"] <= 150_000_000, st["to_command"]
assert 4_000_000 <= st["to_apply"]["min_ns"] and st["to_apply"]["max_ns"] <= 60_000_000, st["to_apply"]
assert abs(sum(s["share"] for s in live["stages"]) - 1) < 1e-9, live
print("live breakdown = stats --stages: %d events, %d complete, %d incomplete; median M2M %.1f ms, "
      "to_command %.2f ms, to_apply %.2f ms (%s commands marked; %.1f s to converge)" %
      (live["events"], live["complete"], live["incomplete"], live["m2m_median_ms"], st["to_command"]["median_ms"],
       st["to_apply"]["median_ms"], open(sys.argv[2]).read().strip(), (time.time_ns() - int(sys.argv[3])) / 1e9))
PY
kill -TERM "$COLLECT_PID"
wait "$COLLECT_PID" || { cat collect.err >&2; fail "collect did not end cleanly"; }
COLLECT_PID=
echo "collect_breakdown: ok"
