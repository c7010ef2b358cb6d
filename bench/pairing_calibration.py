#!/usr/bin/python3
"""Measures how well `--matcher model`'s pair probabilities are calibrated on the simulator: runs
`m2mlat simulate` for seeds 1..N (its truth.csv says which edges belong together), pairs each run with
`m2mlat pair --matcher model`, and prints, per decade of 1 - p, the pairs, the wrong ones and the
expected wrong count (the sum of 1 - p); then the kept pairs' totals and each wrong kept pair's kind
(coincidence: neither edge has a true partner; shifted: both have one elsewhere; half: one has).
Usage: pairing_calibration.py M2MLAT PRESET MAGNETS SEEDS MANOEUVRES WORKDIR
e.g.   pairing_calibration.py build/m2mlat dynamic_co_referenced 45,135,225,315 100 150 /tmp/calibration"""
import csv
import math
import os
import subprocess
import sys


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    m2mlat, preset, magnets, seeds, manoeuvres, work = sys.argv[1:]
    angles = magnets.split(",")
    bins = {}  # decade of 1 - p -> [pairs, wrong, expected]
    kept = wrong = 0
    expected = 0.0
    kinds = {"coincidence": 0, "shifted": 0, "half": 0}
    for seed in range(1, int(seeds) + 1):
        out = os.path.join(work, f"{preset}_{seed}")
        subprocess.run([m2mlat, "simulate", "--scenario", preset, "--seed", str(seed), "--manoeuvres", manoeuvres,
                        "--set", f"magnets_deg={magnets}", "--out-dir", out], check=True, capture_output=True)
        subprocess.run([m2mlat, "pair", "--cause-file", f"{out}/operator.csv", "--effect-file", f"{out}/vehicle.csv",
                        "--magnets", *angles, "--matcher", "model", "-o", f"{out}/pairs.csv"],
                       check=True, capture_output=True)
        causes = [int(r["time_ns"]) for r in rows(f"{out}/operator.csv")]
        effects = [int(r["time_ns"]) for r in rows(f"{out}/vehicle.csv")]
        truth = {causes[int(r["cause_index"])]: effects[int(r["effect_index"])] for r in rows(f"{out}/truth.csv")}
        true_effects = set(truth.values())
        for r in rows(f"{out}/pairs.csv"):
            cause, effect, p = int(r["cause_time_ns"]), int(r["effect_time_ns"]), float(r["probability"])
            right = truth.get(cause) == effect
            decade = 16 if p >= 1 else min(16, int(-math.log10(1 - p)))
            b = bins.setdefault(decade, [0, 0, 0.0])
            b[0] += 1
            b[1] += not right
            b[2] += 1 - p
            if r["in_statistics"] != "true":
                continue
            kept += 1
            expected += 1 - p
            if not right:
                wrong += 1
                partners = (cause in truth) + (effect in true_effects)
                kinds[["coincidence", "half", "shifted"][partners]] += 1
    print(f"{preset}, magnets {magnets}, seeds 1-{seeds}, {manoeuvres} manoeuvres")
    print("1 - p           pairs   wrong   expected")
    for decade in sorted(bins):
        n, w, e = bins[decade]
        label = "< 1e-16" if decade == 16 else f"1e-{decade + 1}..1e-{decade}"
        print(f"{label:<15} {n:>6} {w:>7} {e:>10.2f}")
    print(f"kept: {kept} pairs, {wrong} wrong ({', '.join(f'{v} {k}' for k, v in kinds.items())}), {expected:.2f} expected")


main()
