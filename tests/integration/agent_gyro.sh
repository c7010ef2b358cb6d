# A gyroscope in `m2mlat agent`: an agent with the simulated gyroscope (`--gyro sim`: the register
# twin read by the real driver, sampler and channel) records over two sessions begun through the API;
# the coordinator, killed with SIGKILL and restarted in between, pulls /v1/rate-blocks into the
# campaign store. At the end each session's raw trace in the campaign (`export --what gyro`) equals
# the agent's own byte for byte (every block exactly once), each session's samples lie inside the
# session (a block never crosses a session's end), and the traces show the simulated rotations.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

start_agent vehicle effect 5 vehicle.db 127.0.0.1:0 --gyro sim --gyro-period 1ms --commit-interval 50ms
URL="http://127.0.0.1:$AGENT_PORT"

# wait_samples SESSION N: waits until the agent has committed N raw samples of SESSION. The sessions'
# sample counts are checked below (more than 800 each); a fixed sleep gave them on a quiet machine
# only (a loaded one reads the chip less often, or the agent starts late), so the test waits for
# the samples themselves; 60 s is a safety net.
wait_samples() {
  "$PY" - "$1" "$2" <<'PY' || fail "session $1: fewer than $2 samples committed after 60 s"
import sqlite3, sys, time
session, want = int(sys.argv[1]), int(sys.argv[2])
deadline = time.monotonic() + 60
while time.monotonic() < deadline:
    try:
        con = sqlite3.connect("file:vehicle.db?mode=ro", uri=True, timeout=5)
        try:
            have = con.execute("SELECT coalesce(sum(count), 0) FROM rate_blocks WHERE session_id = ?",
                               (session,)).fetchone()[0]
        finally:
            con.close()
        if have >= want:
            sys.exit(0)
    except sqlite3.OperationalError:  # not created yet
        pass
    time.sleep(0.05)
sys.exit(1)
PY
}

start_collect() {
  "$M2MLAT" collect --agent "$URL" --store campaign.db --quiet >>collect.out 2>>collect.err &
  COLLECT_PID=$!
}
start_collect
sleep 1.5
wait_samples 1 1000
# A second session, begun through the API while the sampler runs: the boundary falls mid-stream.
"$PY" - "$URL" <<'PY'
import json, sys, urllib.request
req = urllib.request.Request(sys.argv[1] + "/v1/sessions", data=json.dumps({"label": "second"}).encode(),
                             method="POST", headers={"Content-Type": "application/json"})
assert json.load(urllib.request.urlopen(req, timeout=10))["session"]["id"] == 2
PY
sleep 0.7
kill -9 "$COLLECT_PID"; wait "$COLLECT_PID" 2>/dev/null || true
sleep 1.5  # blocks committed meanwhile are taken after the restart
start_collect
sleep 1
kill -TERM "$COLLECT_PID"; wait "$COLLECT_PID" || fail "collect did not end cleanly on SIGTERM"
COLLECT_PID=
wait_samples 2 1000
"$M2MLAT" collect --agent "$URL" --store campaign.db --stop-session --duration 1s --quiet >final.out 2>final.err ||
  { cat final.err >&2; fail "the final collect failed"; }

for session in 1 2; do
  "$M2MLAT" export vehicle.db --what gyro --session $session -o "agent-$session.csv"
  "$M2MLAT" export campaign.db --what gyro --session $session -o "campaign-$session.csv"
  cmp "agent-$session.csv" "campaign-$session.csv" ||
    fail "session $session: the campaign's raw trace differs from the agent's"
done

# Sessions bound their samples; the rotations (60 deg/s peaks every 2 s) are in the traces; the
# campaign holds as many blocks as the agent.
"$PY" - <<'PY'
import sqlite3
def q(db, sql):
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    try:
        return con.execute(sql).fetchall()
    finally:
        con.close()
sessions = {i: (s, e) for i, s, e in q("vehicle.db", "SELECT id, start_ns, end_ns FROM sessions ORDER BY id")}
assert len(sessions) == 2 and all(e is not None for _, e in sessions.values()), sessions
total = 0
for sid in (1, 2):
    rows = [l.split(",") for l in open(f"agent-{sid}.csv") if l[0].isdigit()]
    t = [int(r[0]) for r in rows]
    x = [int(r[2]) / 131 for r in rows]
    start, end = sessions[sid]
    assert start <= t[0] and t[-1] <= end, (sid, start, t[0], t[-1], end)
    assert len(t) > 800, (sid, len(t))  # 1 ms period, sessions of 1 s and more
    total += len(t)
    print(f"session {sid}: {len(t)} samples, peak {max(abs(v) for v in x):.1f} deg/s")
peak = max(max(abs(int(l.split(',')[2])) for l in open(f"agent-{s}.csv") if l[0].isdigit()) for s in (1, 2))
assert 55 < peak / 131 < 65, peak / 131
a = q("vehicle.db", "SELECT count(*), sum(count) FROM rate_blocks")[0]
c = q("campaign.db", "SELECT count(*), sum(count) FROM rate_blocks")[0]
assert a == c and a[1] == total, (a, c, total)
print(f"blocks: agent {a[0]}, campaign {c[0]}, {total} samples")
PY
echo "agent_gyro: ok"
