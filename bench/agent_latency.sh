#!/usr/bin/env bash
# The agent's cost and its live latency, with the simulated source: resident memory and CPU while
# (nearly) idle and at about 1000 events/s, and the delay from a commit becoming visible in the store
# to the event arriving on the SSE stream (p50/p99).
#
#   bench/agent_latency.sh path/to/m2mlat [seconds per phase, default 10]
#
# CPU is (utime + stime) from /proc/PID/stat over the phase, as a percentage of one core; RSS is VmRSS.
# The commit time is when a reader polling the store file every 0.5 ms (Python's sqlite3, WAL) first
# sees the event's seq; the arrival time is when the SSE client reads its `id:` line. Both are
# CLOCK_REALTIME in one process, so the figure includes up to ~0.5 ms of polling and the client's own
# scheduling: an upper bound on the server's share.
set -euo pipefail
M2MLAT=$(realpath "$1")
SECONDS_PER_PHASE=${2:-10}
PY=/usr/bin/python3
WORK=$(mktemp -d)
PID=
trap '[ -n "$PID" ] && kill "$PID" 2>/dev/null; wait 2>/dev/null; rm -rf "$WORK"' EXIT
cd "$WORK"

start() {  # start NAME SIM-SET...: an agent on a free port; sets PID and PORT
  local name=$1; shift
  local sets=()
  for s in "$@"; do sets+=(--sim-set "$s"); done
  "$M2MLAT" agent --store "$name.db" --node vehicle --role effect --source sim --quiet --listen 127.0.0.1:0 \
    --port-file "$name.port" "${sets[@]}" > "$name.out" 2> "$name.err" &
  PID=$!
  for _ in $(seq 100); do [ -s "$name.port" ] && break; sleep 0.1; done
  PORT=$(cat "$name.port")
}

# measure NAME: RSS (MiB), CPU (% of a core) and events/s over one phase; with SSE latency when asked.
measure() {
  local name=$1 latency=${2:-}
  $PY - "$PID" "$PORT" "$name.db" "$SECONDS_PER_PHASE" "$latency" <<'PY'
import http.client, json, os, sqlite3, sys, threading, time
pid, port, db, seconds, latency = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], float(sys.argv[4]), sys.argv[5]
tick = os.sysconf("SC_CLK_TCK")
def cpu():
    f = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(f[11]) + int(f[12])) / tick
def rss():
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"): return int(line.split()[1]) / 1024
def last_seq():
    c = http.client.HTTPConnection("127.0.0.1", port); c.request("GET", "/v1/status")
    return json.loads(c.getresponse().read())["last_seq"]
time.sleep(1.0)  # let it settle
visible, arrived, stop = {}, {}, threading.Event()
def poll_store():
    con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    seen = con.execute("SELECT coalesce(max(seq),0) FROM events").fetchone()[0]
    while not stop.is_set():
        top = con.execute("SELECT coalesce(max(seq),0) FROM events").fetchone()[0]
        if top > seen:
            now = time.clock_gettime_ns(time.CLOCK_REALTIME)
            for s in range(seen + 1, top + 1): visible[s] = now
            seen = top
        time.sleep(0.0005)
def read_stream(after):
    c = http.client.HTTPConnection("127.0.0.1", port); c.request("GET", f"/v1/events/stream?after={after}")
    r = c.getresponse()
    while not stop.is_set():
        line = r.fp.readline()
        if not line: break
        if line.startswith(b"id: "): arrived[int(line[4:])] = time.clock_gettime_ns(time.CLOCK_REALTIME)
threads = []
if latency:
    start = last_seq()
    threads = [threading.Thread(target=poll_store, daemon=True), threading.Thread(target=read_stream, args=(start,), daemon=True)]
    for t in threads: t.start()
    time.sleep(0.3)
seq0, cpu0, t0 = last_seq(), cpu(), time.monotonic()
time.sleep(seconds)
seq1, cpu1, t1 = last_seq(), cpu(), time.monotonic()
stop.set()
out = {"rss_mib": round(rss(), 1), "cpu_percent": round(100 * (cpu1 - cpu0) / (t1 - t0), 1),
       "events_per_s": round((seq1 - seq0) / (t1 - t0), 1)}
if latency:
    d = sorted((arrived[s] - visible[s]) / 1e6 for s in arrived if s in visible)
    if d:
        q = lambda p: d[min(len(d) - 1, int(p * len(d)))]
        out.update({"sse_events": len(d), "sse_p50_ms": round(q(0.5), 2), "sse_p99_ms": round(q(0.99), 2),
                    "sse_max_ms": round(d[-1], 2)})
print(json.dumps(out))
PY
}

echo "idle (static_wifi preset: an edge every few seconds):"
start idle
measure idle latency
kill "$PID"; wait "$PID" || true

# About 1000 edges/s on the effect board: 36 magnets over half the wheel, a fast manoeuvre every
# 70-90 ms, every other pass bouncing (the agent applies no refractory period, so bounces are stored).
echo "busy (~1k events/s):"
start busy "magnets_deg=$(seq -s, 0 5 175)" motion.interval_min=70ms motion.interval_max=90ms motion.min_pause=2ms \
  motion.speed_min_deg_s=3500 motion.speed_max_deg_s=3600 vehicle.max_speed_deg_s=3600 vehicle.min_pause=1ms \
  sensor.bounce_probability=0.5 sensor.miss_probability=0
measure busy latency
kill "$PID"; wait "$PID" || true
