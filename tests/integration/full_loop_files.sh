# The full-loop rig's files through `m2mlat stats` and `m2mlat report`: M2M, G2G, E2E and the motion
# durations of the fixtures against an independent computation (Python integers per event, numpy's
# statistics), exclusions counted by reason, every output (table, JSON, CSV, HTML, pgfplots) holding
# them; and bad files (cut, a text field, a wrong header) refused with file and line, exit 65.
source "$(dirname "$0")/lib.bash"
LOOP="$DATA/full_loop/full_loop_small.csv"
REORDERED="$DATA/full_loop/full_loop_reordered.csv"
CAMERA="$DATA/full_loop/camera_latency_small.txt"

"$M2MLAT" stats "$LOOP" "$REORDERED" "$CAMERA" --json --bootstrap 0 --percentile 10,99.9 \
  --threshold 50ms,100ms,150ms > stats.json
"$M2MLAT" stats "$LOOP" "$CAMERA" > stats.txt
grep -q '^full_loop_small  *M2M ' stats.txt || { cat stats.txt >&2; fail "no M2M row in the table"; }
grep -q '^full_loop_small  *E2E ' stats.txt || fail "no E2E row in the table"
grep -q '^camera_latency_small  *G2G ' stats.txt || fail "no G2G row of the camera file"
! grep -q '^camera_latency_small  *M2M' stats.txt || fail "the camera file has no M2M"

"$M2MLAT" report "$LOOP" "$CAMERA" --bootstrap 0 --threshold 50ms,100ms,150ms --out rep > /dev/null
"$M2MLAT" report "$LOOP" --print csv-full-loop --bootstrap 0 --threshold 50ms,100ms,150ms > printed.csv
[ -s rep/full_loop.csv ] || fail "report --out wrote no full_loop.csv"
grep -q 'data-chart="full-loop"' rep/report.html || fail "no full-loop figure in the HTML report"
grep -q 'data-table="full-loop"' rep/report.html || fail "no full-loop table in the HTML report"
grep -q '## Full loop' rep/report.md || fail "no full-loop section in the Markdown report"
for f in full-loop.tex full-loop.dat full-loop-outliers-full_loop_small-E2E.dat; do
  [ -s "rep/pgfplots/$f" ] || fail "pgfplots/$f missing"
done
grep -q 'full-loop.tex' rep/pgfplots/figures.tex || fail "figures.tex does not input full-loop.tex"

$PY - "$LOOP" "$REORDERED" "$CAMERA" stats.json rep/report.json rep/full_loop.csv printed.csv rep/pgfplots/full-loop.dat <<'PY'
import csv, json, sys
import numpy as np
loop, reordered, camera, stats_path, report_path, csv_path, printed_path, dat_path = sys.argv[1:]

def full_loop(path):
    """Per quantity: (values in ns, excluded by reason), with Python's exact integers."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if any(c.strip() for c in r)]
    names = [c.strip() for c in rows[0]]
    q = {k: ([], {"missing": 0, "impossible": 0, "overflow": 0})
         for k in ["m2m", "g2g", "e2e", "vehicle_motion", "station_motion"]}
    def put(key, value, why=None):
        if why: q[key][1][why] += 1
        else: q[key][0].append(value)
    for r in rows[1:]:
        v = {n: (int(c.strip()) if c.strip() else None) for n, c in zip(names, r)}
        def diff(a, b, ordered):
            if v[a] is None or v[b] is None: return None, "missing"
            d = v[a] - v[b]
            return (None, "impossible") if ordered and d < 0 else (d, None)
        m2m = diff("VEHICLE_GY_ON", "STATION_GY_ON", False)
        g2g = diff("PHOTOTRANSISTOR", "LED_ON", True)
        put("m2m", *m2m); put("g2g", *g2g)
        if m2m[1]: put("e2e", None, m2m[1])
        elif g2g[1]: put("e2e", None, g2g[1])
        else: put("e2e", m2m[0] + g2g[0])
        put("vehicle_motion", *diff("VEHICLE_GY_OFF", "VEHICLE_GY_ON", True))
        put("station_motion", *diff("STATION_GY_OFF", "STATION_GY_ON", True))
    return len(rows) - 1, q

def camera_file(path):
    values, excluded = [], {"missing": 0, "impossible": 0, "overflow": 0}
    lines = [l.strip() for l in open(path) if l.strip()]
    assert lines[0] == "LATENCY (ms)"
    for text in lines[1:]:
        whole, _, frac = text.lstrip("-").partition(".")
        ns = int(whole) * 1_000_000 + int((frac + "000000")[:6])
        ns = -ns if text.startswith("-") else ns
        if ns < 0: excluded["impossible"] += 1
        else: values.append(ns)
    return len(lines) - 1, {"g2g": (values, excluded)}

expected = {"full_loop_small": full_loop(loop), "full_loop_reordered": full_loop(reordered),
            "camera_latency_small": camera_file(camera)}
# By hand from the fixture: 10 events, M2M lacks one station onset; G2G has one photo edge before its
# LED; E2E loses both; the vehicle's motion one missing OFF and one OFF before its ON.
assert expected["full_loop_small"][0] == 10
q = expected["full_loop_small"][1]
assert (len(q["m2m"][0]), q["m2m"][1]["missing"]) == (9, 1)
assert (len(q["g2g"][0]), q["g2g"][1]["impossible"]) == (9, 1)
assert (len(q["e2e"][0]), q["e2e"][1]) == (8, {"missing": 1, "impossible": 1, "overflow": 0})
assert q["vehicle_motion"][1] == {"missing": 1, "impossible": 1, "overflow": 0}
assert min(q["m2m"][0]) == -300_000  # the baseline-like event's negative M2M is kept

def check_summary(s, values_ns, where, extra_percentiles=(), thresholds_ms=(50, 100, 150)):
    ms = np.array(values_ns, dtype=np.int64) / 1e6
    assert s["n"] == len(values_ns), (where, s["n"])
    for key, p in [("p5_ms", 5), ("q1_ms", 25), ("median_ms", 50), ("q3_ms", 75), ("p90_ms", 90),
                   ("p95_ms", 95), ("p99_ms", 99)]:
        assert abs(s[key] - np.percentile(ms, p)) < 1e-9, (where, key, s[key], np.percentile(ms, p))
    assert abs(s["iqr_ms"] - (np.percentile(ms, 75) - np.percentile(ms, 25))) < 1e-9, where
    assert abs(s["mean_ms"] - ms.mean()) < 1e-9, where
    assert abs(s["sd_ms"] - ms.std(ddof=1)) < 1e-9, where
    assert s["min"]["ns"] == min(values_ns) and s["max"]["ns"] == max(values_ns), where
    extra = {p["percent"]: p["ms"] for p in s["percentiles"]}
    assert sorted(extra) == sorted(extra_percentiles), (where, extra)
    for p in extra_percentiles:
        assert abs(extra[p] - np.percentile(ms, p)) < 1e-9, (where, p)
    above = [(a["threshold_ns"], a["count"]) for a in s["above"]]
    if "motion" in where:  # a duration: no latency limit applies
        assert above == [], (where, above)
    else:
        assert above == [(t * 1_000_000, sum(1 for v in values_ns if v > t * 1_000_000)) for t in thresholds_ms], (where, above)

doc = json.load(open(stats_path))
assert doc["scenarios"] == [], doc["scenarios"]
got = {r["scenario"]: r for r in doc["full_loop"]}
assert list(got) == ["full_loop_small", "full_loop_reordered", "camera_latency_small"], list(got)
for name, (events, quantities) in expected.items():
    assert got[name]["events"] == events, (name, got[name]["events"])
    assert set(got[name]["quantities"]) == set(quantities), (name, set(got[name]["quantities"]))
    for key, (values, excluded) in quantities.items():
        entry = got[name]["quantities"][key]
        assert entry["excluded"] == excluded, (name, key, entry["excluded"], excluded)
        check_summary(entry["summary"], values, f"{name} {key}", (10, 99.9))
assert got["camera_latency_small"]["format"] == "camera-latency"
assert got["full_loop_small"]["format"] == "full-loop-csv"

# The report's JSON and CSVs hold the same figures.
rep = {r["scenario"]: r for r in json.load(open(report_path))["full_loop"]}
for name in ["full_loop_small", "camera_latency_small"]:
    for key, (values, excluded) in expected[name][1].items():
        check_summary(rep[name]["quantities"][key]["summary"], values, f"report {name} {key}")
with open(csv_path, newline="") as f:
    table = list(csv.DictReader(f))
assert [(r["scenario"], r["quantity"]) for r in table] == [
    ("full_loop_small", k) for k in ["m2m", "g2g", "e2e", "vehicle_motion", "station_motion"]] + [
    ("camera_latency_small", "g2g")], table
for r in table:
    values, excluded = expected[r["scenario"]][1][r["quantity"]]
    ms = np.array(values) / 1e6
    assert int(r["n"]) == len(values)
    assert int(r["excluded_impossible"]) == excluded["impossible"]
    assert abs(float(r["median_ms"]) - np.median(ms)) < 1e-6, r
    assert abs(float(r["p95_ms"]) - np.percentile(ms, 95)) < 1e-6, r
    if "motion" in r["quantity"]:
        assert r["above_100ms_fraction"] == "", r
    else:
        assert abs(float(r["above_100ms_fraction"]) - np.mean(np.array(values) > 100_000_000)) < 1e-6, r
printed = list(csv.DictReader(open(printed_path)))
assert [(r["quantity"], r["median_ms"]) for r in printed] == [(r["quantity"], r["median_ms"]) for r in table[:5]]
# The figure's boxes: M2M, G2G, E2E per file, their medians numpy's.
boxes = [l.split() for l in open(dat_path)][1:]
assert [(b[0], b[1]) for b in boxes] == [("full_loop_small", k) for k in ("M2M", "G2G", "E2E")] + [
    ("camera_latency_small", "G2G")], boxes
for b, key in zip(boxes, ["m2m", "g2g", "e2e"]):
    assert abs(float(b[5]) - np.median(np.array(q[key][0]) / 1e6)) < 1e-6, b
PY

# Two files compare quantity by quantity, like scenarios: the same events in another layout differ by
# nothing; the camera's G2G against the loop's G2G by the difference of their medians.
"$M2MLAT" report "$LOOP" "$REORDERED" "$CAMERA" --bootstrap 0 --print json > compare.json
$PY - compare.json <<'PY'
import json, sys
import numpy as np
doc = json.load(open(sys.argv[1]))
got = {(c["subject"], c["baseline"]): c for c in doc["comparisons"]}
want = [("full_loop_reordered " + q, "full_loop_small " + q) for q in ("M2M", "G2G", "E2E")] + [
    ("camera_latency_small G2G", "full_loop_small G2G"), ("camera_latency_small G2G", "full_loop_reordered G2G")]
assert list(got) == want, list(got)
for q in ("M2M", "G2G", "E2E"):
    c = got[("full_loop_reordered " + q, "full_loop_small " + q)]
    assert c["median_difference_ms"] == 0 and c["mann_whitney"]["p"] == 1, c
loop = {r["scenario"]: r for r in doc["full_loop"]}
c = got[("camera_latency_small G2G", "full_loop_small G2G")]
medians = [loop[n]["quantities"]["g2g"]["summary"]["median_ms"] for n in ("camera_latency_small", "full_loop_small")]
assert abs(c["median_difference_ms"] - (medians[0] - medians[1])) < 1e-9, (c["median_difference_ms"], medians)
assert (c["n_subject"], c["n_baseline"]) == (8, 9), c
PY

# Bad files: refused with file and line, exit 65 (data), no output.
HEADER=VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR
{ echo "$HEADER"; echo 10,20,30,0,40,50; printf '11,21,31,1,41,5'; } > cut.csv
expect_exit 65 "$M2MLAT" stats cut.csv
grep -q 'cut.csv:3' err.txt || { cat err.txt >&2; fail "a cut last line is not named with its line"; }
{ echo "$HEADER"; echo 10,20,30,0,40,50; echo 10,20,thirty,0,40,50; } > text.csv
expect_exit 65 "$M2MLAT" report text.csv --out text-out
grep -q 'text.csv:3: field LED_ON' err.txt || { cat err.txt >&2; fail "a text field is not named"; }
[ ! -e text-out ] || fail "a refused file still wrote a report"
{ echo "VEHICLE_GY_ON,VEHICLE_GY_OFF,LED,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR"; echo 10,20,30,0,40,50; } > header.csv
expect_exit 65 "$M2MLAT" stats header.csv --json
grep -q "header.csv:1: header column 3 is 'LED'" err.txt || { cat err.txt >&2; fail "a wrong header is not named"; }
[ ! -s out.txt ] || fail "a refused file still printed statistics"
{ echo "LATENCY (ms)"; echo 45.1; echo 12.3456789; } > fine.txt
expect_exit 65 "$M2MLAT" stats fine.txt
grep -q 'fine.txt:3: field LATENCY (ms)' err.txt || { cat err.txt >&2; fail "a sub-ns latency is not named"; }
# A full-loop file is not a store's input.
expect_exit 2 "$M2MLAT" import --store c.db "$LOOP"  # usage
grep -q 'full-loop-csv' err.txt || { cat err.txt >&2; fail "import does not say why"; }
[ ! -e c.db ] || fail "a refused import created a store"
echo "full_loop_files: ok"
