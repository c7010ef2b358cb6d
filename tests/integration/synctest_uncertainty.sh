# Per-sample uncertainty through the statistics path: a simulated campaign (whose clock samples the
# simulator records) gives every pair max_error_ns, u_ns and U95_ns columns in `pair` and
# `export --what pairs`, a sample_uncertainty summary in `stats --json` and a table in `stats`; every
# [latency - max_err, latency + max_err] holds the true latency the simulator reports for the same
# seed, and most [latency - U95, latency + U95] do; the sync gate flags, and with --sync-gate-refuse
# removes, the samples above it.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" simulate --store s.db --manoeuvres 40 --seed 11 > /dev/null
"$M2MLAT" simulate --out-dir truth --manoeuvres 40 --seed 11 > /dev/null
"$M2MLAT" pair s.db -o pairs.csv > /dev/null
"$M2MLAT" export s.db --what pairs --format pairs-jsonl -o pairs.jsonl
"$M2MLAT" stats s.db --bootstrap 0 --json > stats.json
"$M2MLAT" stats s.db --bootstrap 0 --kernel-error 1ms > stats.txt
grep -q "per-sample uncertainty" stats.txt || fail "no uncertainty table in the text output"
"$M2MLAT" stats s.db --bootstrap 0 --json --sync-gate 1ms > gated.json
"$M2MLAT" stats s.db --bootstrap 0 --json --sync-gate 1ms --sync-gate-refuse > refused.json
"$M2MLAT" stats s.db --bootstrap 0 --json --sync-gate 1s --sync-gate-refuse > open.json
expect_exit 2 "$M2MLAT" stats s.db --sync-gate-refuse
expect_exit 2 "$M2MLAT" stats s.db --path-u=-5us
grep -q -- "--path-u: '-5us' is negative" err.txt || fail "a negative --path-u is not named: $(cat err.txt)"
expect_exit 2 "$M2MLAT" stats s.db --kernel-u 5
grep -q -- "--kernel-u" err.txt || fail "a bad --kernel-u is not named: $(cat err.txt)"
"$M2MLAT" stats s.db --bootstrap 0 --json --path-u 0us --kernel-u 0us > narrow.json
$PY - <<'PY'
import json
import pandas as pd
pairs = pd.read_csv("pairs.csv")
truth = pd.read_csv("truth/truth.csv")
assert {"max_error_ns", "u_ns", "U95_ns"} <= set(pairs.columns), pairs.columns
assert "est_error_ns" not in pairs.columns and "uncertainty_ns" not in pairs.columns
assert pairs["max_error_ns"].notna().all() and (pairs["u_ns"] > 0).all()
assert ((pairs["U95_ns"] - 2 * pairs["u_ns"]).abs() <= 1).all()  # k = 2
assert (pairs["U95_ns"] < pairs["max_error_ns"]).all()
lines = [json.loads(l) for l in open("pairs.jsonl")]
assert lines[0]["format"] == "m2mlat-pairs/4"
for column in ("max_error_ns", "u_ns", "U95_ns"):
    assert [l[column] for l in lines] == pairs[column].tolist(), column
# The simulator's events are identical for the same seed: pair by measured latency.
true_by_measured = dict(zip(truth.measured_latency_ns, truth.true_latency_ns))
checked = within_U95 = 0
for lat, bound, expanded in zip(pairs.latency_ns, pairs.max_error_ns, pairs.U95_ns):
    if lat not in true_by_measured: continue
    error = abs(lat - true_by_measured[lat])
    assert error <= bound, (lat, true_by_measured[lat], bound)  # the worst case always holds
    within_U95 += error <= expanded
    checked += 1
# About 95 % expected (docs/precision.md); 40 manoeuvres are too few for a tight figure.
assert within_U95 >= 0.8 * checked, (within_U95, checked)
assert checked >= 0.9 * len(pairs), (checked, len(pairs))
s = json.load(open("stats.json"))["scenarios"][0]
# The model's terms are the flags': without the path and kernel terms u is smaller, the bound the same.
n = json.load(open("narrow.json"))["scenarios"][0]["sample_uncertainty"]
assert n["median_u_ms"] < s["sample_uncertainty"]["median_u_ms"], n
assert n["median_max_err_ms"] == s["sample_uncertainty"]["median_max_err_ms"], n
u = s["sample_uncertainty"]
assert u["samples"] == len(pairs) and u["bounded"] == len(pairs) and u["flagged"] == 0, u
assert 0 < u["median_u_ms"] < u["median_U95_ms"] < u["median_max_err_ms"], u
g = json.load(open("gated.json"))["scenarios"][0]
assert g["sample_uncertainty"]["gated"] == len(pairs) and g["latency"]["n"] == s["latency"]["n"]
r = json.load(open("refused.json"))["scenarios"][0]
assert r["sample_uncertainty"]["refused"] == len(pairs) and r["latency"]["n"] == 0
o = json.load(open("open.json"))["scenarios"][0]
assert o["sample_uncertainty"]["gated"] == 0 and o["latency"]["n"] == s["latency"]["n"]
print(checked, "pairs within their bound, %d within U95; median max_err %.3f ms, U95 %.3f ms"
      % (within_U95, u["median_max_err_ms"], u["median_U95_ms"]))
PY
echo "1 passed, 0 failed"
