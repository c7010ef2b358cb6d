#!/usr/bin/env bash
# The coordinator's two figures, with real processes on loopback:
#  1. catch-up rate: an agent store filled by `m2mlat simulate` (about 1M events) is collected from
#     zero with `collect --once`; events stored per second of wall time;
#  2. commit -> stored delay: a paced simulated agent is followed by `collect`; an observer polls
#     the agent's store (largest committed seq) and the campaign store (the origin's cursor) every
#     millisecond and reports, per agent commit, the time until the campaign held it (p50, p99);
#  3. commit -> paired sample on the dashboard: two paced simulated agents (operator = cause,
#     vehicle = effect, one seed) and `collect --dashboard`; an observer polls the vehicle agent's
#     store every millisecond (when each effect event is first visible committed) and follows the
#     dashboard's event stream (when a sample with that effect time first appears in it) (p50, p99).
#     The coordinator's live numbers are the dashboard's: one pairing result feeds both.
# Usage: bench/collect_catchup.sh [M2MLAT] [MANOEUVRES] [FOLLOW_SECONDS]
set -euo pipefail
M2MLAT=$(realpath "${1:-build/m2mlat}")
MANOEUVRES=${2:-55000}  # x 9 magnets x 2 nodes: about 1M events
FOLLOW=${3:-20}
PY=/usr/bin/python3
WORK=$(mktemp -d)
PIDS=()
trap 'for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null || true; done; rm -rf "$WORK"' EXIT
cd "$WORK"

wait_port() {  # LOG: prints the port from "listening 127.0.0.1:PORT"
  for _ in $(seq 300); do
    if grep -qE 'listening 127\.0\.0\.1:[0-9]+' "$1"; then grep -oE 'listening 127\.0\.0\.1:[0-9]+' "$1" | head -n1 | sed 's/.*://'; return; fi
    sleep 0.05
  done
  cat "$1" >&2; exit 1
}

# 1. Catch-up.
"$M2MLAT" simulate --store filled.db --manoeuvres "$MANOEUVRES" --set magnets_deg=0,20,40,60,80,100,120,140,160 >/dev/null
"$M2MLAT" agent --source sim --role effect --node filler --store filled.db --listen 127.0.0.1:0 >filled.log 2>&1 &
PIDS+=($!)
PORT=$(wait_port filled.log)
start=$(date +%s.%N)
"$M2MLAT" collect --agent "http://127.0.0.1:$PORT" --store campaign1.db --once --json >once.json
end=$(date +%s.%N)
$PY - "$start" "$end" <<'PYEOF'
import json, sys
start, end = float(sys.argv[1]), float(sys.argv[2])
events = sum(a["events"] for a in json.load(open("once.json"))["agents"])
print(f"catch-up: {events} events in {end - start:.2f} s = {events / (end - start):,.0f} events/s")
PYEOF

# 2. Commit -> stored.
"$M2MLAT" agent --source sim --sim-paced --sim-set magnets_deg=0,20,40,60,80,100,120,140,160 \
  --role effect --node vehicle --store live.db --listen 127.0.0.1:0 >live.log 2>&1 &
PIDS+=($!)
PORT=$(wait_port live.log)
"$M2MLAT" collect --agent "http://127.0.0.1:$PORT" --store campaign2.db --quiet >collect.out 2>collect.err &
PIDS+=($!)
$PY - live.db campaign2.db "$FOLLOW" <<'PYEOF'
import sqlite3, sys, time
agent_path, campaign_path, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
def connect(path):
    while True:
        try:
            c = sqlite3.connect(f"file:{path}?mode=ro", uri=True, isolation_level=None)
            c.execute("SELECT 1 FROM events LIMIT 1")
            return c
        except sqlite3.Error:
            time.sleep(0.01)
agent, campaign = connect(agent_path), connect(campaign_path)
origin = agent.execute("SELECT value FROM meta WHERE key = 'store_id'").fetchone()[0]
committed = {}  # agent commit (its last seq) -> when first seen, s
stored = {}     # the same seq -> when the campaign first held it
last_agent = last_campaign = 0
end = time.monotonic() + seconds
while time.monotonic() < end:
    now = time.monotonic()
    seq = agent.execute("SELECT coalesce(max(seq), 0) FROM events").fetchone()[0]
    if seq > last_agent:
        committed[seq] = now
        last_agent = seq
    row = campaign.execute("SELECT event_seq FROM origins WHERE origin = ?", (origin,)).fetchone()
    cur = row[0] if row else 0
    if cur > last_campaign:
        for s in committed:
            if last_campaign < s <= cur and s not in stored:
                stored[s] = now
        last_campaign = cur
    time.sleep(0.001)
delays = sorted((stored[s] - committed[s]) * 1000 for s in stored)
if not delays:
    sys.exit("no commit was observed in both stores")
q = lambda p: delays[min(len(delays) - 1, int(p * len(delays)))]
print(f"commit -> stored: {len(delays)} commits, p50 {q(0.5):.1f} ms, p99 {q(0.99):.1f} ms, max {delays[-1]:.1f} ms "
      f"(observer polls every ~1 ms)")
PYEOF

# 3. Commit -> paired sample on the dashboard.
for side in "operator cause" "vehicle effect"; do
  read -r node role <<< "$side"
  "$M2MLAT" agent --source sim --sim-paced --seed 11 --role "$role" --node "$node" --store "pair-$node.db" \
    --sim-set motion.interval_min=700ms --sim-set motion.interval_max=1200ms --listen 127.0.0.1:0 >"pair-$node.log" 2>&1 &
  PIDS+=($!)
done
OP=$(wait_port pair-operator.log)
VE=$(wait_port pair-vehicle.log)
"$M2MLAT" collect --agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE" --store campaign3.db --quiet \
  --no-live --dashboard 127.0.0.1:0 >collect3.out 2>collect3.err &
PIDS+=($!)
for _ in $(seq 200); do grep -q '^dashboard http' collect3.err && break; sleep 0.05; done
URL=$(sed -n 's/^dashboard \(http[^ ]*\)$/\1/p' collect3.err)
[ -n "$URL" ] || { cat collect3.err >&2; exit 1; }
$PY - pair-vehicle.db "${URL}api/live/stream" "$FOLLOW" <<'PYEOF'
import json, sqlite3, sys, threading, time, urllib.request
agent_path, stream_url, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
committed, shown = {}, {}  # effect t_ns -> when first seen committed on the agent / paired on the page, s
end = time.monotonic() + seconds
def follow():
    with urllib.request.urlopen(stream_url, timeout=seconds + 5) as r:
        for line in r:
            if time.monotonic() > end:
                return
            if line.startswith(b"data: "):
                now = time.monotonic()
                for s in json.loads(line[6:])["recent"]:
                    shown.setdefault(s["t_ns"] + s["latency_ns"], now)
threading.Thread(target=follow, daemon=True).start()
while True:
    try:
        agent = sqlite3.connect(f"file:{agent_path}?mode=ro", uri=True, isolation_level=None)
        agent.execute("SELECT 1 FROM events LIMIT 1")
        break
    except sqlite3.Error:
        time.sleep(0.01)
last = 0
while time.monotonic() < end:
    now = time.monotonic()
    for seq, t in agent.execute("SELECT seq, t_ns FROM events WHERE seq > ?", (last,)):
        committed.setdefault(t, now)
        last = max(last, seq)
    time.sleep(0.001)
delays = sorted((shown[t] - committed[t]) * 1000 for t in committed if t in shown)
if not delays:
    sys.exit("no effect event was seen both committed and paired on the dashboard")
q = lambda p: delays[min(len(delays) - 1, int(p * len(delays)))]
print(f"commit -> paired on the dashboard: {len(delays)} of {len(committed)} effect events, p50 {q(0.5):.1f} ms, "
      f"p99 {q(0.99):.1f} ms, max {delays[-1]:.1f} ms (observer polls every ~1 ms)")
PYEOF
