# The demo: finishes in under 30 s, and its statistics use no pair that disagrees with the truth.
source "$(dirname "$0")/lib.bash"
start=$(date +%s)
"$M2MLAT" demo --json > demo.json
elapsed=$(( $(date +%s) - start ))
[ "$elapsed" -lt 30 ] || fail "demo took $elapsed s"
"$M2MLAT" demo --magnets 0,20,40 --json > demo3.json
"$M2MLAT" demo > demo.txt
grep -q "per-sample uncertainty against the truth" demo.txt || fail "no coverage table in the demo's text"
$PY - demo.json demo3.json <<'PY'
import json, sys
for path in sys.argv[1:]:
    doc = json.load(open(path))
    assert doc["format"] == "m2mlat-stats/1"
    names = [s["scenario"] for s in doc["scenarios"]]
    assert names == ["static_wifi", "static_5g", "dynamic_co_referenced", "dynamic_autonomous"], names
    for s in doc["scenarios"]:
        t = s["truth"]
        assert t["wrong_not_ambiguous"] == 0, (path, s["scenario"], t)
        assert t["passes"] and t["found_pct"] >= 95, (path, s["scenario"], t)  # the acceptance criterion
        median = s["latency"]["median_ms"]
        assert 700 <= median <= 1000, (s["scenario"], median)  # the reference study's range, roughly
        assert abs(median - t["true_median_ms"]) < 15, (s["scenario"], median, t)  # ambiguous pairs are left out
        assert t["max_abs_error_ns"] < 5_000_000, t  # clocks + interrupt latency: a few ms at most
        # The per-sample uncertainty against the truth (docs/precision.md; ~70 pairs a scenario, so
        # loose here: the unit test's seed sweep holds the calibration to 93-97 %).
        c = t["uncertainty"]
        assert c["pairs"] == t["correct"] and c["coverage_max_error"] == 1.0, (s["scenario"], c)
        assert c["coverage_U95"] >= 0.85 and c["coverage_u"] < c["coverage_U95"], (s["scenario"], c)
        assert 1.5 <= c["width_ratio"] <= 5, (s["scenario"], c)
    by = {s["scenario"]: s["latency"] for s in doc["scenarios"]}
    assert by["static_5g"]["iqr_ms"] < by["static_wifi"]["iqr_ms"], "5G spread should be narrower"
    assert by["dynamic_co_referenced"]["median_ms"] < by["static_wifi"]["median_ms"], "moving: smaller actuator lag"
print("demo ok")
PY
# The self-check: exit 1 exactly when a scenario lets a wrong pair through unflagged or finds fewer
# than 95 % of the true pairs (seed 11 did so with the matcher of its time; either way the exit
# status must agree with the report).
rc=0
"$M2MLAT" demo --seed 11 --scenario static_wifi --scenario stalls --magnets 0,90,180,270 --json > check.json || rc=$?
$PY - check.json "$rc" <<'PY'
import json, sys
doc, rc = json.load(open(sys.argv[1])), int(sys.argv[2])
for s in doc["scenarios"]:
    t = s["truth"]
    assert t["wrong"] == t["wrong_flagged"] + t["wrong_unflagged"], t
    assert abs(t["found_pct"] - 100.0 * t["correct"] / t["true_pairs"]) < 1e-9, t
    assert t["passes"] == (t["wrong_unflagged"] == 0 and 100 * t["correct"] >= 95 * t["true_pairs"]), t
want = 0 if all(s["truth"]["passes"] for s in doc["scenarios"]) else 1
assert rc == want, (rc, want)
PY
# Simulator settings apply to every scenario; a bad one stops the demo before any store exists.
expect_exit 2 "$M2MLAT" demo --store bad.db --set network.stall_per_minute=-1
grep -q "network.stall_per_minute" err.txt || fail "the error does not name the setting: $(cat err.txt)"
[ ! -e bad.db ] || fail "a refused demo left a store"
"$M2MLAT" demo --scenario static_5g --set network.stall_per_minute=4 --json > stalled.json || true
$PY - stalled.json <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["scenarios"][0]["truth"]
assert t["true_median_ms"] > 0 and t["true_pairs"] > 50, t
PY
echo "1 passed, 0 failed"
