# Lines recorded with both edges, and interference on them (--min-pulse, pairing/glitch_filter.hpp):
# a pulse of microseconds where a missed pass's edge would have been is paired, unflagged, with one
# edge a pass; with --min-pulse it is dropped and counted, from a data file and from a store alike.
source "$(dirname "$0")/lib.bash"
$PY - <<'PY'
import random
random.seed(7)
t0 = 1_700_000_000_000_000_000
MS = 1_000_000
rows = []
def pulse(node, t, width):
    rows.append((node, "falling", t))
    rows.append((node, "rising", t + width))
for k in range(40):
    c = t0 + k * 3000 * MS
    pulse("operator", c, 12 * MS + random.randrange(4 * MS))
    if k == 20:  # the vehicle's pass is missed; interference where it would have been
        pulse("vehicle", c + 760 * MS, 4_000)
    else:
        pulse("vehicle", c + 800 * MS + random.randrange(-40 * MS, 40 * MS), 15 * MS + random.randrange(5 * MS))
for k in (3, 11, 27):  # more interference, away from the passes
    pulse("operator", t0 + k * 3000 * MS + 1500 * MS, 2_000)
    pulse("vehicle", t0 + k * 3000 * MS + 2200 * MS, 20_000)
rows.sort(key=lambda r: r[2])
with open("both.csv", "w") as f:
    f.write("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n")
    for node, edge, t in rows:
        f.write(f"{node},wheel,{edge},realtime,{t},0,0,0\n")
PY
"$M2MLAT" stats both.csv --json --min-pulse off > plain.json
"$M2MLAT" stats both.csv --json --min-pulse 1ms > filtered.json
# The default (auto) filters at 1 ms where both lines hold both edges.
"$M2MLAT" stats both.csv --json > automatic.json
cmp automatic.json filtered.json || fail "--min-pulse auto is not 1ms on lines with both edges"
"$M2MLAT" stats both.csv --min-pulse 1ms > filtered.txt
grep -q "both: 3 cause and 4 effect edges started no pulse of 1.000 ms" filtered.txt || { cat filtered.txt; fail "no note of the filter"; }
"$M2MLAT" import --store s.db both.csv > /dev/null
"$M2MLAT" stats s.db --json --min-pulse 1ms > store.json
$PY - <<'PY'
import json
def scenario(path):
    return json.load(open(path))["scenarios"][0]
plain, filtered, store = scenario("plain.json"), scenario("filtered.json"), scenario("store.json")
# Without the filter the interference at 760 ms is a pair like the others, and so are the pulses on
# both lines 700 ms apart: 43 pairs, every one in the statistics, no flag saying otherwise.
assert plain["pairing"]["pairs"] == 43 and plain["latency"]["n"] == 43, plain
assert "glitches" not in plain["pairing"], plain["pairing"]
for s in (filtered, store):
    p = s["pairing"]
    assert p["glitches"] == {"min_pulse_ns": 1_000_000, "cause": 3, "effect": 4}, p
    assert p["pairs"] == 39, p
    assert p["cause_events"] == 40 and p["effect_events"] == 39, p
    # the pair after the cause left without its effect is flagged competing (docs/matcher.md)
    assert s["latency"]["n"] == 38, s["latency"]
PY
# A line with one kind of edge has no pulse width: refused, naming it; so is --min-pulse with both kinds paired.
grep -v ",rising," both.csv > falling.csv
expect_exit 65 "$M2MLAT" stats falling.csv --min-pulse 1ms
grep -q "operator/wheel has falling edges only" err.txt || { cat err.txt; fail "the refusal names no line"; }
expect_exit 2 "$M2MLAT" stats both.csv --min-pulse 1ms --edge both
expect_exit 2 "$M2MLAT" stats both.csv --min-pulse soon
echo "interference: ok"
