#!/usr/bin/env bash
# A real cyclictest run of 2 s through `m2mlat schedtest` (SCHED_FIFO 99 needs root, as in CI):
# the printed summary, the JSON, and the result stored as a session labelled "schedtest".
source "$(dirname "$0")/lib.bash"
command -v cyclictest >/dev/null || fail "cyclictest (rt-tests) is not installed"
[ "$(id -u)" = 0 ] || fail "needs root: cyclictest runs at SCHED_FIFO 99 with mlockall"
CPU=$($PY -c 'import os; print(max(os.sched_getaffinity(0)))')

"$M2MLAT" schedtest --core "$CPU" --duration 2s --histogram-us 200 --store s.db --node board-a --json >run.json
$PY - "$CPU" <<'PY' || fail "schedtest JSON: $(cat run.json)"
import json, sqlite3, sys
cpu = int(sys.argv[1])
d = json.load(open("run.json"))
assert d["kind"] == "schedtest" and d["tool"] == "cyclictest", d
assert d["settings"] == {"cpu": cpu, "priority": 99, "interval_us": 1000, "duration_s": 2, "histogram_us": 200}, d["settings"]
assert "--mlockall" in d["cmdline"] and f"--affinity={cpu}" in d["cmdline"], d["cmdline"]
[t] = d["threads"]
assert t["cpu"] == cpu and 1000 <= t["cycles"] <= 2001, t  # late wake-ups on a busy CI machine lose cycles
assert 0 <= t["min_us"] <= t["avg_us"] <= t["max_us"], t
assert sum(n for _, n in t["histogram"]) + t["overflows"] == t["cycles"], t
assert d["end_ns"] - d["start_ns"] >= 2 * 10**9, d
db = sqlite3.connect("s.db")
rows = db.execute("SELECT id, label, node, role, config_json, end_ns - start_ns FROM sessions").fetchall()
assert len(rows) == 1 and rows[0][0] == d["session_id"], rows
_, label, node, role, config, length = rows[0]
assert label == "schedtest" and node == "board-a" and role == 2, rows
stored = json.loads(config)
del d["session_id"]
assert stored == d, (stored, d)
assert length == d["end_ns"] - d["start_ns"]
PY

"$M2MLAT" schedtest --core "$CPU" --duration 1s >run.txt 2>run.err
grep -Eq "^cpu $CPU: [0-9]+ wake-ups, latency min [0-9]+ us, avg [0-9.]+ us, max [0-9]+ us" run.txt || fail "$(cat run.txt)"
grep -Eq "^ +[0-9-]+ us +[0-9]+ #+" run.txt || fail "no histogram: $(cat run.txt)"

expect_exit 2 "$M2MLAT" schedtest --core "$CPU" --duration 1500ms
expect_exit 2 "$M2MLAT" schedtest --core -1 --duration 1s
expect_exit 2 "$M2MLAT" schedtest --core 4096 --duration 1s  # beyond the machine: named, not cyclictest's warning
grep -q -- "--core 4096: this process may run on CPUs" err.txt || fail "$(cat err.txt)"
expect_exit 74 "$M2MLAT" schedtest --core "$CPU" --duration 1s --cyclictest /nonexistent/cyclictest
echo "schedtest: ok"
