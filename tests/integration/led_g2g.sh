# `m2mlat led` on a machine without GPIO, and glass-to-glass from files: every wrong way of asking for
# the LED is a clear error with its exit code, a missing chip leaves a store as it was, and a
# single-board G2G (the LED and the phototransistor as two channels of one node, its clock not
# synchronised) pairs LED on with photo edge and is bounded by the clock's drift and the circuit term
# only. (Driving a real line is tested in the real kernel: tests/vm, g2g.led-photo.)
source "$(dirname "$0")/lib.bash"

# Usage errors (exit 2), each naming what to fix.
expect_exit 2 "$M2MLAT" led --chip gpiochip0 --line 1
grep -q "choose one trigger" err.txt || fail "no trigger: $(cat err.txt)"
expect_exit 2 "$M2MLAT" led --chip gpiochip0 --line 1 --period 1s --stdin
grep -q "choose one trigger" err.txt || fail "two triggers: $(cat err.txt)"
expect_exit 2 "$M2MLAT" led --chip gpiochip0 --line 1 --stdin --count 3
grep -q -- "--count and --duration go with --period" err.txt || fail "count without schedule: $(cat err.txt)"
expect_exit 2 "$M2MLAT" led --chip gpiochip0 --line 1 --stdin --store s.db
grep -q -- "--store and --events need --node" err.txt || fail "store without node: $(cat err.txt)"
[ ! -e s.db ] || fail "a store was created by a refused command"

# A missing chip: exit 66 naming it; a store already there keeps its content, byte for byte.
"$M2MLAT" simulate --manoeuvres 3 --store keep.db >/dev/null 2>&1
cp keep.db keep.before
expect_exit 66 "$M2MLAT" led --chip gpiochip7 --line 1 --period 1s --store keep.db --node vehicle
grep -q "no GPIO chip 'gpiochip7'" err.txt || fail "missing chip: $(cat err.txt)"
cmp -s keep.db keep.before || fail "the store was changed by a run that could not start"

# Single board: one node's LED (commanded, rising at each flash) and photo channels, 200 ms apart,
# G2G 20.00 + 0.01 i ms; the node's clock unsynchronised (adjtimex: 16 ms bounds).
$PY - <<'PY'
base = 1_764_000_000_000_000_000
rows = ["# format: m2mlat-events/1"]
for k in range(3):
    rows.append('# clock: {"node":"bench","clock":"realtime","time_ns":%d,"source":"adjtimex",'
                '"offset_ns":0,"max_error_ns":16000000,"est_error_ns":16000000,"synchronised":false,'
                '"detail":{}}' % (base + k * 2_000_000_000))
rows.append("node,channel,edge,clock,time_ns,seqno,line_seqno,flags")
for i in range(20):
    t = base + i * 200_000_000
    rows += [f"bench,led,rising,realtime,{t},0,0,20", f"bench,led,falling,realtime,{t + 50_000_000},0,0,20",
             f"bench,photo,rising,realtime,{t + 20_000_000 + i * 10_000},{2 * i + 1},{2 * i + 1},0",
             f"bench,photo,falling,realtime,{t + 70_000_000},{2 * i + 2},{2 * i + 2},0"]
open("bench.csv", "w").write("\n".join(rows) + "\n")
PY
"$M2MLAT" stats bench.csv --cause bench/led --effect bench/photo --edge rising --calibration-error 50us \
  --calibration-u 20us --json >bench.json
$PY - bench.json <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))["scenarios"][0]
lat, u = s["latency"], s["sample_uncertainty"]
assert s["cause"] == "bench/led" and s["effect"] == "bench/photo", s
assert lat["n"] == 20, lat["n"]
assert abs(lat["median_ms"] - 20.095) < 1e-9, lat["median_ms"]
# One clock stamped both: no unsynchronised flag, and the bound is the drift over 20 ms (15 ppm:
# 301.5 ns -> 302 ns) plus the 50 us circuit term, not twice the board's 16 ms.
assert u["unsynchronised"] == 0 and u["flagged"] == 0 and u["bounded"] == 20, u
assert 0.0502 <= u["median_max_err_ms"] <= 0.0504, u["median_max_err_ms"]
# u: sqrt(drift^2 + 2 kernel_u^2 + calibration_u^2) = sqrt(0.17^2 + 2 x 5^2 + 20^2) us = 21.21 us.
assert 0.0211 <= u["median_u_ms"] <= 0.0213, u["median_u_ms"]
PY
echo "PASS"
