// Mann-Whitney U test (Wilcoxon rank-sum) of two independent samples: is one sample's distribution
// shifted against the other's? Rank-based, so it needs no assumption of normality and is not pulled
// by a few very long latencies.
//
// Definition (as scipy.stats.mannwhitneyu with its default method="auto", use_continuity=True): pool
// both samples, give tied values their average rank; U_a = R_a - n_a (n_a + 1) / 2 where R_a is the
// sum of sample a's ranks; U_b = n_a n_b - U_a. The two-sided p comes from the normal approximation
// with the tie correction of the variance and a continuity correction of 1/2:
//   sigma^2 = n_a n_b / 12 * ((n + 1) - sum(t^3 - t) / (n (n - 1)))    (t: size of each tie group)
//   z = (max(U_a, U_b) - n_a n_b / 2 - 1/2) / sigma,   p = min(1, 2 P(Z > z)),
// except, as in SciPy, when a sample has at most 8 values and there are no ties: then from U's exact
// distribution, p = min(1, 2 P(U <= min(U_a, U_b))) (where the approximation can be off by orders of
// magnitude: 5 values against 201 gave 2.7e-9 exactly, 1.5e-4 approximated). Documented in
// docs/report.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace m2mlat::stats {

// The exact distribution is used when the smaller sample has at most kExactMaxSize values (SciPy's
// rule), there are no ties, and the tail to sum has fewer than kExactMaxTail terms (16 B each).
inline constexpr std::size_t kExactMaxSize = 8;
inline constexpr std::size_t kExactMaxTail = std::size_t{1} << 20;

struct MannWhitney {
  std::size_t n_a = 0, n_b = 0;
  double u_a = 0.0;  // U of sample a: pairs (x in a, y in b) with x > y, ties counting 1/2
  double z = 0.0;    // standardised max(U_a, U_b), continuity-corrected
  double p = 1.0;    // two-sided p value; 1 when undefined (an empty sample or all values equal)
  bool exact = false;  // p from U's exact distribution (else the normal approximation)
  // Common-language effect size U_a / (n_a n_b): the probability that a random value of a exceeds
  // a random value of b (ties counting 1/2). 0.5 = no shift.
  double probability_a_greater = 0.5;
};

// Samples in ns (any order; compared exactly as integers).
MannWhitney mann_whitney(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns);

}  // namespace m2mlat::stats
