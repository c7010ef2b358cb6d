# The demo's full-loop scenarios: chains from the simulated gyroscopes, LED and camera path, with M2M,
# G2G and E2E side by side and their errors against the truth; the reference detector's lag fails it.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" demo --scenario full_loop --scenario full_loop_baseline --scenario full_loop_single_board \
  --manoeuvres 20 --json > loop.json
"$M2MLAT" demo --scenario full_loop --manoeuvres 10 > loop.txt
grep -q "E2E = M2M + G2G" loop.txt || fail "no full-loop table in the demo's text"
grep -q "against the simulator's truth" loop.txt || fail "no truth check in the demo's text"
$PY - loop.json <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
loops = {r["scenario"]: r for r in doc["full_loop"]}
truth = {t["scenario"]: t for t in doc["full_loop_truth"]}
assert set(loops) == {"full_loop", "full_loop_baseline", "full_loop_single_board"}, loops.keys()
for name, t in truth.items():
    assert t["passes"] and t["complete"] == t["manoeuvres"] == 20 and t["duplicate"] == 0, t
    assert loops[name]["format"] == "chains" and sum(loops[name]["incomplete_chains"].values()) == 0
assert set(loops["full_loop_single_board"]["quantities"]) == {"g2g"}  # one board: G2G alone
full = loops["full_loop"]["quantities"]
assert set(full) == {"m2m", "g2g", "e2e", "vehicle_motion", "station_motion"}, full.keys()
# E2E = M2M + G2G per chain: the means add up.
m = {q: full[q]["summary"]["mean_ms"] for q in ("m2m", "g2g", "e2e")}
assert abs(m["m2m"] + m["g2g"] - m["e2e"]) < 1e-6, m
# The baseline: true M2M = 0; the flank detector's median M2M error (sync offsets included) small.
b = truth["full_loop_baseline"]["errors"]["M2M"]
assert abs(b["median_ns"]) < 500_000 and b["n"] == 20, b
print("full loop demo ok")
PY
rc=0
"$M2MLAT" demo --scenario full_loop --manoeuvres 10 --detector reference > ref.txt || rc=$?
[ "$rc" = 1 ] || fail "the reference detector's lag passed the truth check (rc $rc)"
grep -q FAIL ref.txt || fail "no FAIL shown for the reference detector"
