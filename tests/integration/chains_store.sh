# The full loop from recorded data: a simulated full-loop run recorded as two board stores (the station's
# gyroscope and phototransistor, the vehicle's gyroscope and `m2mlat led` session), joined by `m2mlat
# merge`; `stats` and `report` chain them and give the demo's M2M, G2G and E2E for the same seed;
# the two board stores given as cause and effect give the same; a Hall scenario in the same store is
# still paired; a missing board or photo channel is named.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" simulate --scenario full_loop --seed 5 --manoeuvres 15 --board station --store station.db > /dev/null
"$M2MLAT" simulate --scenario full_loop --seed 5 --manoeuvres 15 --board vehicle --store vehicle.db > /dev/null
"$M2MLAT" merge campaign.db station.db vehicle.db > /dev/null
"$M2MLAT" stats campaign.db --json > merged.json
"$M2MLAT" stats --cause-file station.db --effect-file vehicle.db --json > boards.json
"$M2MLAT" demo --scenario full_loop --seed 5 --manoeuvres 15 --json > demo.json
"$M2MLAT" stats campaign.db > merged.txt
grep -q "E2E = M2M + G2G" merged.txt || fail "no full-loop table from the store"
grep -q "full_loop: incomplete chains: none" merged.txt || fail "incomplete chains not counted"
$PY - merged.json boards.json demo.json <<'PY'
import json, sys
merged, boards, demo = (json.load(open(p))["full_loop"] for p in sys.argv[1:4])
assert len(merged) == len(boards) == len(demo) == 1, (merged, boards, demo)
m, b, d = merged[0], boards[0], demo[0]
assert m["scenario"] == "full_loop" and m["format"] == "chains" and m["events"] == 15, m
assert sum(m["incomplete_chains"].values()) == 0, m["incomplete_chains"]
for q in ("m2m", "g2g", "e2e", "vehicle_motion", "station_motion"):
    for other in (b, d):
        assert m["quantities"][q]["summary"] == other["quantities"][q]["summary"], (q, m["quantities"][q], other)
    assert m["quantities"][q]["summary"]["n"] == 15, q
print("chains from stores = the demo's chains")
PY

# The report: the same table, the full-loop CSV, the HTML figure and the pgfplots figure.
"$M2MLAT" report campaign.db --out rep > /dev/null
grep -q "^full_loop,campaign.db: chains (flank),e2e,15,15," rep/full_loop.csv || { cat rep/full_loop.csv >&2; fail "no E2E row in full_loop.csv"; }
grep -q 'data-chart="full-loop"' rep/report.html || fail "no full-loop figure in the HTML report"
[ -s rep/pgfplots/full-loop.tex ] || fail "no full-loop pgfplots figure"

# Another detector is a flag away; an unknown one is a usage error.
"$M2MLAT" stats campaign.db --detector reference > reference.txt
grep -q "chains (reference)" <("$M2MLAT" stats campaign.db --detector reference --json) ||
  fail "the reference detector not named"
expect_exit 2 "$M2MLAT" stats campaign.db --detector nope

# A Hall scenario beside the full loop is still paired as events.
"$M2MLAT" simulate --scenario static_wifi --manoeuvres 20 --store campaign.db > /dev/null
"$M2MLAT" stats campaign.db > mixed.txt
grep -q "E2E = M2M + G2G" mixed.txt || fail "the full loop lost beside a Hall scenario"
grep -q "static_wifi" mixed.txt || fail "the Hall scenario not paired beside the full loop"

# What is missing is named, and the exit code is the data error's.
expect_exit 65 "$M2MLAT" stats station.db
grep -q "station.db: scenario 'full_loop' has no vehicle (effect node) with a gyroscope trace" err.txt ||
  { cat err.txt >&2; fail "a missing vehicle trace not named"; }
expect_exit 65 "$M2MLAT" stats campaign.db --photo-channel light
grep -q "no photo edges on station/light (its channels: photo)" err.txt ||
  { cat err.txt >&2; fail "a missing photo channel not named"; }
# A full loop without gyroscopes cannot be a store's; nothing is made.
expect_exit 2 "$M2MLAT" simulate --scenario full_loop_single_board --store single.db
[ ! -e single.db ] || fail "a refused simulate made a store"
echo "chains from stores ok"
