#!/usr/bin/python3
"""The baseline the benchmark compares against: import -> pair -> statistics written the way a
researcher would with Python, numpy and pandas (Debian's python3-numpy and python3-pandas).

Input: two kernel-log files (lines "GPIO_<pin>_IRQ:<ns>", as the reference rig's kernel module wrote
them), the cause side and the effect side. Import: pandas.read_csv with ':' as the separator,
keeping only the timestamp column.

Pairing, vectorised with numpy, for a wheel with several magnets (each manoeuvre gives a burst of
edges tens of ms apart on each side, ~0.9 s latency between the sides):
  1. drop bounces: an edge less than 10 ms after the previous edge of its side;
  2. the typical latency: the fullest 20 ms bin of all cause -> effect differences inside the
     0..3 s window (on a subsample of 10^5 causes);
  3. cut each side into bursts (a gap of more than 300 ms starts a new one), pair each cause burst
     with the effect burst that starts nearest to its start + the typical latency, and the edges of
     two paired bursts in order (first with first, ...);
  4. keep pairs inside the window, each effect used once.
This is simpler and less robust than m2mlat's matcher (no local reference, a missed edge shifts
the rest of its burst), so the comparison favours the baseline; on the benchmark's simulated
recording it finds as many pairs, ~97% of them right.

Statistics: the same set m2mlat computes (n, min, max, mean, sd, P5/Q1/median/Q3/P90/P95/P99, IQR,
shares above thresholds, bootstrap CIs of median and IQR with the same number of resamples, each
resample drawn with numpy's generator and its quantiles taken with numpy.percentile). Prints one
JSON object, with the seconds spent in each step under "timing_s".
"""
import json
import sys
import time

import numpy as np
import pandas as pd

WINDOW_NS = (0, 3_000_000_000)
THRESHOLDS_MS = (170, 300, 400, 1000)
BOUNCE_NS = 10_000_000
BIN_NS = 20_000_000
BURST_GAP_NS = 300_000_000


def load(path):
    frame = pd.read_csv(path, sep=":", header=None, usecols=[1], names=["tag", "ns"], dtype={"ns": np.int64})
    return np.sort(frame["ns"].to_numpy())


def debounce(t):
    keep = np.ones(len(t), dtype=bool)
    keep[1:] = np.diff(t) >= BOUNCE_NS
    return t[keep]


def typical_latency(cause, effect):
    sub = cause[:: max(1, len(cause) // 100_000)]
    lo = np.searchsorted(effect, sub + WINDOW_NS[0])
    hi = np.searchsorted(effect, sub + WINDOW_NS[1], side="right")
    count = hi - lo
    offset = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    diff = effect[np.repeat(lo, count) + offset] - np.repeat(sub, count)
    hist, edges = np.histogram(diff, bins=np.arange(WINDOW_NS[0], WINDOW_NS[1] + BIN_NS, BIN_NS))
    return edges[hist.argmax()] + BIN_NS // 2


def bursts(t):
    new = np.ones(len(t), dtype=bool)
    new[1:] = np.diff(t) > BURST_GAP_NS
    starts = np.flatnonzero(new)
    return np.cumsum(new) - 1, starts, np.diff(np.append(starts, len(t)))


def burst_partners(cause, effect, latency0):
    """For each cause edge, the index of its effect edge by burst and rank (may be out of range)."""
    cause_burst, cause_start, _ = bursts(cause)
    _, effect_start, effect_count = bursts(effect)
    # Each cause burst -> the effect burst starting nearest to its start + the typical latency.
    first = effect[effect_start]
    target = cause[cause_start] + latency0
    i = np.searchsorted(first, target).clip(1, max(1, len(first) - 1))
    partner = np.where(target - first[i - 1] <= first[i] - target, i - 1, i)[cause_burst]
    rank = np.arange(len(cause)) - cause_start[cause_burst]
    del cause_burst
    ok = rank < effect_count[partner]
    return np.flatnonzero(ok), effect_start[partner[ok]] + rank[ok]


def pair(cause, effect):
    cause, effect = debounce(cause), debounce(effect)
    ci, ej = burst_partners(cause, effect, typical_latency(cause, effect))
    latency = effect[ej] - cause[ci]
    keep = (latency >= WINDOW_NS[0]) & (latency <= WINDOW_NS[1])
    latency, ej = latency[keep], ej[keep]
    _, once = np.unique(ej, return_index=True)  # one effect, one cause: keep the earliest
    return latency[np.sort(once)]


def statistics(ms):
    q = np.percentile(ms, [5, 25, 50, 75, 90, 95, 99])
    return {
        "n": int(len(ms)), "min_ms": float(ms.min()), "max_ms": float(ms.max()),
        "mean_ms": float(ms.mean()), "sd_ms": float(ms.std(ddof=1)),
        "p5": q[0], "q1": q[1], "median": q[2], "q3": q[3], "p90": q[4], "p95": q[5], "p99": q[6],
        "iqr": q[3] - q[1],
        "above": {str(t): float((ms > t).mean()) for t in THRESHOLDS_MS},
    }


def bootstrap(ms, resamples, seed=1):
    rng = np.random.default_rng(seed)
    medians, iqrs = [], []
    for _ in range(resamples):
        sample = ms[rng.integers(0, len(ms), len(ms))]
        q1, med, q3 = np.percentile(sample, [25, 50, 75])
        medians.append(med)
        iqrs.append(q3 - q1)
    return {
        "median_ci": list(np.percentile(medians, [2.5, 97.5])) if resamples else None,
        "iqr_ci": list(np.percentile(iqrs, [2.5, 97.5])) if resamples else None,
    }


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: baseline.py CAUSE.log EFFECT.log [BOOTSTRAP_RESAMPLES]")
    resamples = int(sys.argv[3]) if len(sys.argv) == 4 else 100
    timing = {}
    start = time.perf_counter()
    cause, effect = load(sys.argv[1]), load(sys.argv[2])
    timing["import"] = time.perf_counter() - start
    start = time.perf_counter()
    latency = pair(cause, effect)
    timing["pair"] = time.perf_counter() - start
    start = time.perf_counter()
    ms = latency.astype(np.float64) / 1e6
    result = statistics(ms)
    timing["statistics"] = time.perf_counter() - start
    start = time.perf_counter()
    result.update(bootstrap(ms, resamples))
    timing["bootstrap"] = time.perf_counter() - start
    result["events"] = {"cause": int(len(cause)), "effect": int(len(effect))}
    result["timing_s"] = {k: round(v, 3) for k, v in timing.items()}
    print(json.dumps(result, default=float))


if __name__ == "__main__":
    main()
