# The stage breakdown end to end: `simulate --markers` writes a run's events, each command's markers
# (stamped on the simulated boards' clocks) and the stage rule; `stats --markers --stages` cuts every
# event into stages that add up to its M2M to the nanosecond (checked here from the per-event CSV and
# against the events files), the JSON's shares add up to 1; markers removed from the file come back
# as incomplete chains with the right count; `report` draws the stacked bars (HTML, pgfplots); bad
# rules and marker files exit 2 and 65 naming the file, the line and the field.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" simulate --scenario static_5g --manoeuvres 60 --seed 7 --out-dir run --markers >/dev/null
[ -s run/markers.csv ] && [ -s run/stages.txt ] || fail "simulate --markers wrote no markers.csv or stages.txt"
files=(--cause-file run/operator.csv --effect-file run/vehicle.csv)
"$M2MLAT" stats "${files[@]}" --markers run/markers.csv --stages run/stages.txt --breakdown-csv bd.csv \
  --json >stats.json
"$M2MLAT" pair "${files[@]}" -o pairs.csv >/dev/null
$PY - <<'PYEOF'
import csv, json
d = json.load(open("stats.json"))["scenarios"][0]
b = d["breakdown"]
assert b["incomplete"] == 0 and b["complete"] == b["events"] > 40, b
names = [s["name"] for s in b["stages"]]
assert names == ["operator_software", "send", "network", "vehicle_software", "actuator"], names
assert abs(sum(s["share"] for s in b["stages"]) - 1) < 1e-9, b
rows = list(csv.reader(open("bd.csv")))  # the header first, no comment line
head, rows = rows[0], rows[1:]
assert head[:7] == ["scenario", "pair", "cause_id", "cause_ns", "effect_ns", "m2m_ns", "status"], head
events = {}
for r in rows:
    e = events.setdefault(int(r[1]), {"m2m": int(r[5]), "cause": int(r[3]), "effect": int(r[4]), "stages": []})
    e["stages"].append((r[9], int(r[10])))
assert len(events) == b["events"], (len(events), b)
# The pairs' own latencies, from the pair export: the stages add up to each to the nanosecond.
pairs = {}
for r in csv.DictReader(l for l in open("pairs.csv") if not l.startswith("#")):
    pairs[int(r["cause_time_ns"])] = int(r["latency_ns"])
for e in events.values():
    assert [s for s, _ in e["stages"]] == names, e
    assert sum(v for _, v in e["stages"]) == e["m2m"] == e["effect"] - e["cause"], e
    assert pairs[e["cause"]] == e["m2m"], e
    assert all(v >= 0 for _, v in e["stages"]), e
PYEOF
# Markers lost: every receive of an even command removed: those events' chains stop at the network.
awk -F, '!($2 == "receive" && $6 % 2 == 0)' run/markers.csv >lost.csv
"$M2MLAT" stats "${files[@]}" --markers lost.csv --stages run/stages.txt --json >lost.json
"$M2MLAT" stats "${files[@]}" --markers lost.csv --stages run/stages.txt >lost.txt
$PY - <<'PYEOF'
import json
full = json.load(open("stats.json"))["scenarios"][0]["breakdown"]
b = json.load(open("lost.json"))["scenarios"][0]["breakdown"]
removed = sum(1 for l in open("run/markers.csv") if ",receive," in l and int(l.split(",")[5]) % 2 == 0)
assert b["events"] == full["events"] and b["incomplete"] > 0, b
assert b["complete"] + b["incomplete"] == b["events"], b
assert b["incomplete_by_reason"] == [{"stage": "network", "reason": "missing", "count": b["incomplete"]}], b
assert b["incomplete"] <= removed, (b, removed)
PYEOF
grep -q "incomplete: [0-9]* missing at network" lost.txt || fail "terminal: $(cat lost.txt)"
# The report: the stacked bars in the HTML page and the pgfplots figure, the per-event rows.
"$M2MLAT" report "${files[@]}" --markers run/markers.csv --stages run/stages.txt --out rep >/dev/null
grep -q 'data-chart="breakdown"' rep/report.html || fail "no breakdown chart in the HTML report"
grep -q "Where the time goes" rep/report.html || fail "no breakdown section in the HTML report"
[ -s rep/breakdown.csv ] && [ -s rep/pgfplots/breakdown.tex ] && [ -s rep/pgfplots/breakdown.dat ] ||
  fail "report --out: no breakdown.csv or pgfplots/breakdown.tex"
grep -q "breakdown.tex" rep/pgfplots/figures.tex || fail "figures.tex does not input breakdown.tex"
# Bad input: a rule with a bad selector (usage, 2), a marker file with a bad field (data, 65), markers
# without a rule, a missing marker file (66).
printf 'a = first operator:send after the cause\nz = effect\n' >bad-stages.txt
expect_exit 2 "$M2MLAT" stats "${files[@]}" --markers run/markers.csv --stages bad-stages.txt
grep -q "bad-stages.txt:1: selector: 'first operator:send after the cause' is not one of" err.txt ||
  fail "bad rule: $(cat err.txt)"
sed '3s/,realtime,[0-9]*,/,realtime,12x,/' run/markers.csv >bad-markers.csv
expect_exit 65 "$M2MLAT" stats "${files[@]}" --markers bad-markers.csv --stages run/stages.txt
grep -q "bad-markers.csv:3: field time_ns" err.txt || fail "bad marker: $(cat err.txt)"
expect_exit 2 "$M2MLAT" stats "${files[@]}" --markers run/markers.csv
expect_exit 66 "$M2MLAT" stats "${files[@]}" --markers nothing.csv --stages run/stages.txt
echo "breakdown: ok"
