#!/usr/bin/python3
"""Reference values for the m2mlat::stats unit tests, computed independently of the C++ code.

Run with Debian's interpreter (it has numpy):  /usr/bin/python3 tests/unit/stats/reference_values.py

Descriptive statistics come from numpy (np.percentile's default method is Hyndman-Fan type 7;
np.std with ddof=1) and from Python's statistics module (exact rational arithmetic for mean and
stdev). The pseudo-random generator (splitmix64, xoshiro256**, the two-per-word bounded draws)
is re-implemented here from its definition in Python integers, and the bootstrap's draws of a
resample's order statistics (normal, gamma, Beta variates and the portable logarithm) operation by
operation in Python floats (IEEE doubles), so the C++ tests can check the exact resamples. Every constant in the tests is printed by this script,
with the name the test uses.
"""

import math
import statistics
import struct

import numpy as np

MASK64 = (1 << 64) - 1
PERCENTS = [0, 5, 12.5, 25, 50, 75, 90, 95, 99, 99.9, 100]


def show(name, value):
    if isinstance(value, float):
        print(f"{name} = {value!r}")
    else:
        print(f"{name} = {value}")


# --- descriptive statistics -----------------------------------------------------------------


def describe(label, values_ns):
    """Everything summarize() reports, ns in, ms out (as the C++ Summary)."""
    x = np.array(values_ns, dtype=np.int64)
    n = len(values_ns)
    print(f"\n# {label}: n = {n}")
    show(f"{label}.min_ns", int(x.min()))
    show(f"{label}.min_index", int(np.argmin(x)))  # first of ties
    show(f"{label}.max_ns", int(x.max()))
    show(f"{label}.max_index", int(np.argmax(x)))
    # statistics.mean is exact (Fraction) then rounded once; the division by 1e6 as in C++.
    show(f"{label}.mean_ms", float(statistics.mean(values_ns)) / 1e6)
    if n >= 2:
        sd_exact = statistics.stdev(values_ns)
        sd_numpy = float(np.std(x, ddof=1))
        assert abs(sd_exact - sd_numpy) <= 1e-12 * max(sd_exact, 1.0), (sd_exact, sd_numpy)
        show(f"{label}.sd_ms", sd_exact / 1e6)
    for p in PERCENTS:
        show(f"{label}.P{p}_ms", float(np.percentile(x, p)) / 1e6)
    iqr = float(np.percentile(x, 75)) - float(np.percentile(x, 25))
    show(f"{label}.iqr_ms", iqr / 1e6)
    for t_ms in (170, 300, 400, 1000):
        above = int(np.count_nonzero(x > t_ms * 1_000_000))
        show(f"{label}.above_{t_ms}ms", above)


# Small hand-made samples (ns). The tests hold the same literals.
SAMPLES = {
    "one": [812_345_678],
    "two": [250_000_001, 150_000_000],
    "odd_ties": [5_000_000, 3_000_000, 3_000_000, 9_000_000, 1_000_000, 7_000_000, 3_000_000],
    "even_negative": [-2_000_000, 500, -7, 1_000_000_000, 3, 3, 42, -2_000_000],
    "thresholds": [170_000_000, 170_000_001, 299_999_999, 300_000_000, 300_000_001, 400_000_000,
                   999_999_999, 1_000_000_000, 1_000_000_001, 12_000, 2_500_000_000],
}


def lcg_sample(n, seed):
    """Latencies from Knuth's MMIX LCG: 120 ms plus 0..899.999999 ms (the tests' LcgSample)."""
    state = seed
    out = []
    for _ in range(n):
        state = (state * 6364136223846793005 + 1442695040888963407) & MASK64
        out.append(120_000_000 + (state >> 33) % 900_000_000)
    return out


# --- the generator ---------------------------------------------------------------------------


class SplitMix64:
    def __init__(self, state):
        self.state = state & MASK64

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK64
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
        return z ^ (z >> 31)


def rotl(x, k):
    return ((x << k) | (x >> (64 - k))) & MASK64


class Xoshiro256ss:
    def __init__(self, words):
        self.s = list(words)

    @staticmethod
    def stream(seed, stream):
        sm = SplitMix64(seed + 4 * stream * 0x9E3779B97F4A7C15)
        return Xoshiro256ss([sm.next() for _ in range(4)])

    def next(self):
        s = self.s
        result = (rotl((s[1] * 5) & MASK64, 7) * 9) & MASK64
        t = (s[1] << 17) & MASK64
        s[2] ^= s[0]
        s[3] ^= s[1]
        s[1] ^= s[2]
        s[0] ^= s[3]
        s[2] ^= t
        s[3] = rotl(s[3], 45)
        return result

    def below(self, bound):
        """Lemire: high half of next() * bound, redrawn while the low half < 2^64 mod bound."""
        threshold = (1 << 64) % bound
        while True:
            m = self.next() * bound
            if (m & MASK64) >= threshold:
                return m >> 64


class IndexStream:
    """Two 32-bit candidates per output (high half first); Lemire's rejection in 32 bits."""

    def __init__(self, rng, bound):
        self.rng, self.bound = rng, bound
        self.threshold = (1 << 32) % bound
        self.pending = []

    def next(self):
        while True:
            if not self.pending:
                w = self.rng.next()
                self.pending = [w >> 32, w & 0xFFFFFFFF]
            x = self.pending.pop(0)
            m = x * self.bound
            if (m & 0xFFFFFFFF) >= self.threshold:
                return m >> 32


# --- a resample's order statistics (order_statistics.hpp) ---------------------------------------


def uniform01(rng):
    return float(rng.next() >> 11) * (1.0 / 9007199254740992.0)


LN2_HIGH = float.fromhex("0x1.62e42fee00000p-1")
LN2_LOW = float.fromhex("0x1.a39ef35793c76p-33")
SQRT_TWO = 1.41421356237309504880168872420969808
ODD_INVERSE = [1.0 / float(2 * k + 1) for k in range(11)]


def portable_log(x):
    """core::portable_log, operation by operation (Python floats are IEEE doubles, no fused ops)."""
    if not x > 0:
        return float("-inf")
    bits = struct.unpack("<Q", struct.pack("<d", x))[0]
    exponent = 0
    if (bits >> 52) == 0:
        bits = struct.unpack("<Q", struct.pack("<d", x * float.fromhex("0x1.0p54")))[0]
        exponent = -54
    exponent += (bits >> 52) - 1023
    m = struct.unpack("<d", struct.pack("<Q", (bits & 0x000FFFFFFFFFFFFF) | 0x3FF0000000000000))[0]
    if m >= SQRT_TWO:
        m *= 0.5
        exponent += 1
    s = (m - 1) / (m + 1)
    s2 = s * s
    series = ODD_INVERSE[10]
    for k in range(9, -1, -1):
        series = ODD_INVERSE[k] + s2 * series
    e = float(exponent)
    return e * LN2_HIGH + (e * LN2_LOW + 2 * s * series)


def normal_variate(rng):
    while True:
        x = 2.0 * uniform01(rng) - 1.0
        y = 2.0 * uniform01(rng) - 1.0
        s = x * x + y * y
        if s < 1.0 and s > 0.0:
            return x * math.sqrt(-2.0 * portable_log(s) / s)


def gamma_variate(rng, shape):
    d = shape - 1.0 / 3.0
    c = 1.0 / math.sqrt(9.0 * d)
    while True:
        while True:
            x = normal_variate(rng)
            v = 1.0 + c * x
            if v > 0.0:
                break
        v = v * v * v
        u = uniform01(rng)
        x2 = x * x
        if u < 1.0 - 0.0331 * x2 * x2:
            return d * v
        if portable_log(u) < 0.5 * x2 + d * (1.0 - v + portable_log(v)):
            return d * v


def resample_order_statistics(rng, n, wanted):
    """The wanted-th smallest (0-based, ascending) of n ranks drawn from 0..n-1: U_(k) of n uniforms
    is Beta(k, n - k + 1), and the next one is Beta-distributed above it."""
    below, placed, ranks = 0.0, 0, []
    for j in wanted:
        k = j + 1
        x = gamma_variate(rng, float(k - placed))
        y = gamma_variate(rng, float(n - k + 1))
        below = below + (1.0 - below) * (x / (x + y))
        placed = k
        ranks.append(min(n - 1, int(below * float(n))))
    return ranks


def bootstrap_median_iqr(values_ns, resamples, seed, level):
    """The bootstrap as defined in bootstrap.hpp: each resample's order statistics drawn, placed in a
    sorted stand-in resample (each filled up to the next), and its quartiles by numpy."""
    x = np.sort(np.array(values_ns, dtype=np.int64))
    n = len(x)
    wanted = set()
    for p in (0.25, 0.5, 0.75):
        h = (n - 1) * p
        wanted.add(int(math.floor(h)))
        if h != math.floor(h):
            wanted.add(int(math.floor(h)) + 1)
    wanted = sorted(wanted)
    medians, iqrs = [], []
    for b in range(resamples):
        ranks = resample_order_statistics(Xoshiro256ss.stream(seed, b), n, wanted)
        stand_in = np.empty(n, dtype=np.int64)
        for i, j in enumerate(wanted):
            end = wanted[i + 1] if i + 1 < len(wanted) else n
            stand_in[(0 if i == 0 else j):end] = x[ranks[i]]
        q1, med, q3 = np.percentile(stand_in, [25, 50, 75])
        medians.append(float(med))
        iqrs.append(float(q3) - float(q1))
    probs = [(1.0 - level) / 2.0, (1.0 + level) / 2.0]
    med_ci = np.quantile(np.array(medians), probs)
    iqr_ci = np.quantile(np.array(iqrs), probs)
    return medians, iqrs, [float(v) / 1e6 for v in med_ci], [float(v) / 1e6 for v in iqr_ci]


def main():
    print("# Generated by tests/unit/stats/reference_values.py (numpy", np.__version__ + ")")
    for label, values in SAMPLES.items():
        describe(label, values)
    describe("lcg10007", lcg_sample(10007, 42))

    print("\n# Exact means whose sums leave int64")
    int64_max, int64_min = (1 << 63) - 1, -(1 << 63)
    for label, values in {"near_max": [int64_max, int64_max, int64_max - 1],
                          "near_min": [int64_min, int64_min, -1]}.items():
        q, r = divmod(sum(values), len(values))
        show(f"{label}.floor_ns", q)
        show(f"{label}.remainder", r)
        show(f"{label}.mean_ns", float(statistics.mean(values)))
    show("far_offset.sd_ns", statistics.stdev([10**18 + d for d in (0, 1, 2, 3)]))

    print("\n# Generator outputs")
    a, b = 0x123456789ABCDEF, 0xFEDCBA987654321
    print(f"wide product 0x{a:x} * 0x{b:x}: high = 0x{(a * b) >> 64:x}, low = 0x{(a * b) & MASK64:x}")
    sm = SplitMix64(1234567)
    show("splitmix64(1234567)", [sm.next() for _ in range(5)])
    rng = Xoshiro256ss.stream(1, 0)
    show("Rng(1).next", [rng.next() for _ in range(4)])
    rng = Xoshiro256ss.stream(7, 3)
    show("Rng::stream(7, 3).next", [rng.next() for _ in range(2)])
    rng = Xoshiro256ss.stream(99, 0)
    show("Rng(99).below(1000)", [rng.below(1000) for _ in range(6)])
    rng = Xoshiro256ss.stream(99, 0)
    show("Rng(99).below(3<<62)", [rng.below(3 << 62) for _ in range(6)])
    draw = IndexStream(Xoshiro256ss.stream(5, 0), 10)
    show("IndexStream(Rng(5), 10)", [draw.next() for _ in range(12)])
    # 2^32 mod 3e9 = 1294967296: about 30 % of candidates are rejected.
    draw = IndexStream(Xoshiro256ss.stream(5, 0), 3_000_000_000)
    show("IndexStream(Rng(5), 3e9)", [draw.next() for _ in range(12)])

    print("\n# Order statistics of a resample")
    show("normal_variate(Rng(9))", normal_variate(Xoshiro256ss.stream(9, 0)))
    rng = Xoshiro256ss.stream(9, 1)
    show("gamma_variate(Rng::stream(9, 1), 1 then 1e6)", [gamma_variate(rng, 1.0), gamma_variate(rng, 1e6)])
    show("ranks(Rng::stream(2024, 0), 10007, [2501, 2502, 5003])",
         resample_order_statistics(Xoshiro256ss.stream(2024, 0), 10007, [2501, 2502, 5003]))

    for (n, sample_seed, resamples, seed, level, name) in ((25, 7, 300, 2024, 0.95, "boot"),
                                                           (1000, 3, 50, 8, 0.9, "boot1000")):
        print(f"\n# Bootstrap of lcg_sample({n}, {sample_seed}), B = {resamples}, seed = {seed}, level {level}")
        medians, iqrs, med_ci, iqr_ci = bootstrap_median_iqr(lcg_sample(n, sample_seed), resamples, seed, level)
        show(f"{name}.median_ns[0..2]", medians[:3])
        show(f"{name}.iqr_ns[0..2]", iqrs[:3])
        show(f"{name}.median_ci_ms", med_ci)
        show(f"{name}.iqr_ci_ms", iqr_ci)

if __name__ == "__main__":
    main()
