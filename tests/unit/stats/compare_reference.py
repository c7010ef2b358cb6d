#!/usr/bin/python3
# Reference values of the comparison tests (compare_test.cpp), computed with SciPy (Debian's
# python3-scipy): Mann-Whitney U, Brown-Forsythe (Levene, center="median"), the distributions behind
# them, and Newcombe's interval (its formula, with scipy's normal quantile). Run it and compare its
# output with the constants in compare_test.cpp:  /usr/bin/python3 tests/unit/stats/compare_reference.py
import numpy as np
from scipy import stats

# The samples of the test, in ns: latencies with ties, of different sizes.
A = [812_000_000 + ((i * 7_919_003) % 97) * 3_000_000 for i in range(31)] + [812_000_000, 1_305_000_000]
B = [760_000_000 + ((i * 5_003_011) % 89) * 2_000_000 for i in range(27)] + [812_000_000, 812_000_000]
C = [700_000_000, 700_000_000, 700_000_000, 800_000_000]

def show(name, value):
    print(f"  {name} = {value!r}")

print("A =", A)
print("B =", B)
r = stats.mannwhitneyu(A, B, alternative="two-sided", method="asymptotic", use_continuity=True)
show("mw(A,B).u", float(r.statistic)); show("mw(A,B).p", float(r.pvalue))
r = stats.mannwhitneyu(B, A, alternative="two-sided", method="asymptotic", use_continuity=True)
show("mw(B,A).u", float(r.statistic)); show("mw(B,A).p", float(r.pvalue))
r = stats.mannwhitneyu(C, B, alternative="two-sided", method="asymptotic", use_continuity=True)
show("mw(C,B).u", float(r.statistic)); show("mw(C,B).p", float(r.pvalue))
r = stats.levene(A, B, center="median")
show("bf(A,B).w", float(r.statistic)); show("bf(A,B).p", float(r.pvalue))
r = stats.levene(A, B, C, center="median")
show("bf(A,B,C).w", float(r.statistic)); show("bf(A,B,C).p", float(r.pvalue))
show("norm.cdf(-1.5)", stats.norm.cdf(-1.5)); show("norm.sf(6.0)", stats.norm.sf(6.0))
show("norm.ppf(0.975)", stats.norm.ppf(0.975))
show("t.sf(2.1, 7)", stats.t.sf(2.1, 7)); show("f.sf(3.2, 2, 40)", stats.f.sf(3.2, 2, 40))
show("beta.cdf(0.3, 2.5, 4)", stats.beta.cdf(0.3, 2.5, 4))

def wilson(k, n, z):
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)

def newcombe(k1, n1, k2, n2, level):
    z = stats.norm.ppf(0.5 + level / 2)
    p1, p2 = k1 / n1, k2 / n2
    l1, u1 = wilson(k1, n1, z)
    l2, u2 = wilson(k2, n2, z)
    d = p1 - p2
    return d - np.sqrt((p1 - l1) ** 2 + (u2 - p2) ** 2), d + np.sqrt((u1 - p1) ** 2 + (p2 - l2) ** 2)

show("newcombe(6,63,9,66,0.95)", newcombe(6, 63, 9, 66, 0.95))
show("newcombe(0,50,3,40,0.90)", newcombe(0, 50, 3, 40, 0.90))
