# The seed sweep: the demo's truth check over seeds 1..100 x the five presets (the study's four and
# stalls) x four magnet layouts (0; 0,30; 0,20,40; 0,90,180,270), odd seeds with harsher sensors
# (10 % of the operator's passes missed, 10 % bounces, 2 spurious edges a minute on the vehicle).
# Criterion per run (docs/simulator.md, "The truth check"): no wrong pair unflagged, >= 95 % of the
# true pairs found. With M2MLAT_SWEEP_STRICT=1 a failing run fails the test; by default it prints the
# table and passes while the full sweep is no worse than its recorded figures (at most 6 wrong pairs
# unflagged and 508 failing runs: the matcher of this writing does not meet the criterion;
# docs/testing.md).
# A demo that exits other than 0 (pass) or 1 (self-check failed) fails the test either way.
source "$(dirname "$0")/lib.bash"
SEEDS=${M2MLAT_SWEEP_SEEDS:-100}
HARSH="--set cause_sensor.miss_probability=0.1 --set sensor.bounce_probability=0.1 --set effect_sensor.spurious_per_minute=2"

# One demo run: seed, layout ("-" for the presets' one magnet); writes run-<seed>-<layout>.json.
one_run() {
  local seed=$1 layout=$2 args=()
  [ "$layout" = - ] || args+=(--magnets "$layout")
  [ $((seed % 2)) = 0 ] || read -ra harsh <<< "$HARSH"
  local rc=0
  "$M2MLAT" demo --seed "$seed" "${args[@]}" ${harsh[@]+"${harsh[@]}"} --json \
    --scenario static_wifi --scenario static_5g --scenario dynamic_co_referenced \
    --scenario dynamic_autonomous --scenario stalls > "run-$seed-$layout.json" 2> "run-$seed-$layout.err" || rc=$?
  [ "$rc" = 0 ] || [ "$rc" = 1 ] || { echo "demo --seed $seed --magnets $layout exited $rc" >&2; cat "run-$seed-$layout.err" >&2; return 1; }
}
export -f one_run
export M2MLAT HARSH

start=$(date +%s)
for seed in $(seq 1 "$SEEDS"); do
  for layout in - 0,30 0,20,40 0,90,180,270; do echo "$seed $layout"; done
done | xargs -P 2 -n 2 bash -c 'one_run "$@"' _ || fail "a demo run broke (not a self-check result)"
elapsed=$(( $(date +%s) - start ))

$PY - "$SEEDS" "$elapsed" "${M2MLAT_SWEEP_STRICT:-0}" "$HARSH" <<'PY'
import collections, glob, json, re, sys
seeds, elapsed, strict, harsh = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3] == "1", sys.argv[4]
scenarios = ["static_wifi", "static_5g", "dynamic_co_referenced", "dynamic_autonomous", "stalls"]
rows = collections.OrderedDict()
failing = []
for path in sorted(glob.glob("run-*.json")):
    seed, layout = re.match(r"run-(\d+)-(.*)\.json", path).groups()
    sensors = "harsh" if int(seed) % 2 else "field"
    for s in json.load(open(path))["scenarios"]:
        t = s["truth"]
        # The report must agree with itself: passes <=> the criterion on its own counts.
        assert t["passes"] == (t["wrong_unflagged"] == 0 and 100 * t["correct"] >= 95 * t["true_pairs"]), t
        key = ("1" if layout == "-" else layout, sensors, s["scenario"])
        r = rows.setdefault(key, collections.Counter())
        r["runs"] += 1
        r["failing"] += not t["passes"]
        r["wrong_unflagged"] += t["wrong_unflagged"]
        r["wrong_flagged"] += t["wrong_flagged"]
        r["true"] += t["true_pairs"]
        r["correct"] += t["correct"]
        r["below95"] += 100 * t["correct"] < 95 * t["true_pairs"]
        if not t["passes"]:
            # The demo gives its k-th scenario seed + k: the command that repeats this one run.
            failing.append(f"m2mlat demo --seed {int(seed) + scenarios.index(s['scenario'])} "
                           f"--scenario {s['scenario']}" + ("" if layout == "-" else f" --magnets {layout}")
                           + (f" {harsh}" if sensors == "harsh" else ""))
total = collections.Counter()
print(f"{'magnets':<13} {'sensors':<6} {'scenario':<22} {'runs':>5} {'failing':>7} {'<95% found':>10} "
      f"{'wrong unflagged':>15} {'wrong flagged':>13} {'found %':>8}")
layouts = ["1", "0,30", "0,20,40", "0,90,180,270"]
for (layout, sensors, scenario), r in sorted(rows.items(), key=lambda kv: (
        layouts.index(kv[0][0]), kv[0][1] != "field", scenarios.index(kv[0][2]))):
    total.update(r)
    print(f"{layout:<13} {sensors:<6} {scenario:<22} {r['runs']:>5} {r['failing']:>7} {r['below95']:>10} "
          f"{r['wrong_unflagged']:>15} {r['wrong_flagged']:>13} {100 * r['correct'] / r['true']:>8.2f}")
print(f"{'all':<13} {'':<6} {'':<22} {total['runs']:>5} {total['failing']:>7} {total['below95']:>10} "
      f"{total['wrong_unflagged']:>15} {total['wrong_flagged']:>13} {100 * total['correct'] / total['true']:>8.2f}")
assert total["runs"] == seeds * 4 * 5, total["runs"]
print(f"seed sweep: {total['runs']} runs in {elapsed} s, {total['failing']} failing the criterion"
      + ("" if strict else " (report only; M2MLAT_SWEEP_STRICT=1 asserts)"))
if strict and failing:
    print("failing runs (first 20):", *failing[:20], sep="\n  ")
    sys.exit(1)
# Until then the figures of the full sweep may only get better (docs/matcher.md, "Measured accuracy").
if seeds == 100 and (total["wrong_unflagged"] > 6 or total["failing"] > 508):
    print("worse than the recorded figures: at most 6 wrong pairs unflagged and 508 failing runs")
    print("failing runs (first 20):", *failing[:20], sep="\n  ")
    sys.exit(1)
PY
echo "1 passed, 0 failed"
