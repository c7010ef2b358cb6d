# A kernel log's clock that slews is no clock step (issue 16's class): the simulated rig's kernel
# logs (static_5g, three magnets, a poor sensor) analysed with default flags.
#  - the daemon slewing at most 500 ppm (the default, as m2mlat's chrony.conf): no step is seen and
#    the median is the truth's;
#  - a daemon slewing up to chrony's default 83333 ppm: the log's realtime - printk stamps move by
#    ms and back; no step may be corrected from that (a 13-step "correction" once moved the median
#    by 19 ms), stats says so in its clock-steps section, and the median is still the truth's;
#  - the same with the vehicle's clock stepped +40 ms: that step stands out and is corrected.
source "$(dirname "$0")/lib.bash"

SIM=(--format kernel-log --scenario static_5g --manoeuvres 20000 --seed 1 --set magnets_deg=0,20,40
     --set sensor.miss_probability=0.01 --set sensor.bounce_probability=0.03 --set sensor.spurious_per_minute=0.2)

# check DIR WANT: stats --json on DIR's two logs; WANT is none (no clock-steps section), slewing (fast
# slewing reported, nothing corrected) or step (one vehicle step, pairs corrected, slewing reported).
# The median must be within 1.5 ms of the truth's median latency.
check() {
  "$M2MLAT" stats --cause-file "$1/operator.log" --effect-file "$1/vehicle.log" --json > "$1.json"
  "$PY" - "$1" "$2" <<'PYEOF'
import csv, json, statistics, sys
d, want = sys.argv[1], sys.argv[2]
s = json.load(open(f"{d}.json"))["scenarios"][0]
truth = statistics.median(int(r["true_latency_ns"]) for r in csv.DictReader(open(f"{d}/truth.csv"))) / 1e6
median = s["latency"]["median_ms"]
assert abs(median - truth) < 1.5, (d, median, truth)
steps = s.get("clock_steps")
if want == "none":
    assert steps is None, (d, steps)
else:
    assert steps["fast_slew_places"] > 0 and steps["cause_steps"] == 0, (d, steps)
    assert any("slews faster than 500 ppm" in n for n in steps["notes"]), (d, steps)
    if want == "slewing":
        assert steps["effect_steps"] == 0 and steps["pairs_corrected"] == 0, (d, steps)
    else:
        assert steps["effect_steps"] == 1 and steps["pairs_corrected"] > 1000, (d, steps)
print(f"{d}: median {median:.2f} ms, truth {truth:.2f} ms, clock steps {steps}")
PYEOF
}

"$M2MLAT" simulate --out-dir bounded "${SIM[@]}" > /dev/null
check bounded none
"$M2MLAT" simulate --out-dir fast "${SIM[@]}" --set sync.max_slew_ppm=83333 > /dev/null
check fast slewing
# The text output says it in its clock-steps section.
"$M2MLAT" stats --cause-file fast/operator.log --effect-file fast/vehicle.log > fast.txt
grep -q "^note: fast: vehicle: the kernel log's realtime clock slews faster than 500 ppm at [0-9]* places" fast.txt ||
  fail "no slewing note: $(cat fast.txt)"
"$M2MLAT" simulate --out-dir stepped "${SIM[@]}" --set sync.max_slew_ppm=83333 \
  --set effect_clock.step_at=3000s --set effect_clock.step=40ms > /dev/null
check stepped step
echo "kernel_log_slewing: ok"
