# Sessions survive their agents: two simulated agents and `collect --start-session` as real processes;
# the vehicle's agent is killed (SIGKILL) mid-run and started again on its store. It goes on with the
# run's session (scenario and label) at once, the campaign holds every event of both agents exactly
# once, and the run is one scenario: every vehicle session after the start is in it, none "unnamed".
# A second time its store is replaced by a new one (nothing to resume from): the coordinator sees a
# session that is not the run's and begins the run's session on it again.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

start_pair 7

"$M2MLAT" collect --agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE" --store campaign.db \
  --start-session --label run-1 --scenario track --stop-session --duration 9s --json >collect.json 2>collect.err &
COLLECT_PID=$!
sleep 2.5
kill -KILL "$VE_PID"
wait "$VE_PID" 2>/dev/null || true
sleep 0.5
start_agent vehicle effect 8 vehicle.db "127.0.0.1:$VE" --sim-paced  # resumes the cut session's run
sleep 2.5
kill -KILL "$AGENT_PID"
wait "$AGENT_PID" 2>/dev/null || true
start_agent vehicle effect 9 vehicle2.db "127.0.0.1:$VE" --sim-paced  # a new store: the coordinator rejoins it
wait "$COLLECT_PID" || { cat collect.err >&2; fail "collect failed"; }
grep -q "rejoined the run as session" collect.err || { cat collect.err >&2; fail "collect did not rejoin the new agent"; }

$PY - campaign.db <<'PY'
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
rows = db.execute("select id, node, scenario, label from sessions order by id").fetchall()
# The campaign numbers sessions as it takes them: compare the vehicle's sessions with each other only.
vehicle = [r for r in rows if r[1] == "vehicle"]
first_run = min(i for i, n, s, l in vehicle if s == "track")
after = [r for r in vehicle if r[0] > first_run]
track = [r for r in vehicle if r[2] == "track"]
assert len(track) >= 3, f"the vehicle's run is not in 3 sessions of 'track': {rows}"
assert all(r[3] == "run-1" for r in track), f"sessions of another run: {rows}"
# After the run began, only the new store's own first session (before collect rejoined it) is not the run's.
outside = [r for r in after if r[2] != "track"]
assert len(outside) <= 1, f"the restarted vehicle opened sessions outside the run: {rows}"
print(f"ok: {len(rows)} sessions, the vehicle's run in {len(track)} sessions of 'track'")
PY
expect_exactly_once campaign.db operator.db operator
# The run is one scenario: all of its events, the restarted agent's with them.
"$M2MLAT" stats campaign.db --scenario track --json >stats.json
$PY - stats.json <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]["pairing"]
assert s["effect_events"] > 0 and s["cause_events"] > 0, s
print(f"ok: the run holds {s['cause_events']} cause and {s['effect_events']} effect events")
PY
# What the agents recorded before the run began is no scenario beside it: said, not analysed.
"$M2MLAT" stats campaign.db --bootstrap 0 >all.txt
grep -q "events were recorded outside any run" all.txt || { cat all.txt; fail "no word of the events outside the run"; }
grep -q "^unnamed " all.txt && { cat all.txt; fail "the events outside any run shown as a scenario"; }
"$M2MLAT" stats campaign.db --scenario unnamed --bootstrap 0 | grep -q "^unnamed " || fail "--scenario unnamed analyses nothing"
echo "collect_rejoin: ok"
