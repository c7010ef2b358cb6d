// Mann-Whitney U from one merge of the two sorted samples: tie groups are found in integers, so the
// ranks (and U, kept as twice its value in integers) are exact for any sample size.
#include "m2mlat/stats/mann_whitney.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "m2mlat/stats/distributions.hpp"

namespace m2mlat::stats {

namespace {

// P(U <= u) under the null hypothesis without ties, for samples of m and n values: the number of
// orderings of the pooled sample with U <= u over all C(m + n, m) of them. The counts by U are the
// coefficients of the Gaussian binomial [m + n choose m]_q = prod_{i=1..m} (1 - q^(n+i)) / (1 - q^i);
// only those up to q^u are needed. Dividing by (1 - q^i) first (partitions into parts <= m: running
// sums of positive terms), multiplying after. Long double: the counts are ~C(m + n, m) at most.
double exact_cdf(std::size_t m, std::size_t n, std::size_t u) {
  std::vector<long double> count(u + 1, 0.0L);
  count[0] = 1.0L;
  for (std::size_t i = 1; i <= m; ++i)
    for (std::size_t k = i; k <= u; ++k) count[k] += count[k - i];
  for (std::size_t i = 1; i <= m; ++i)  // downwards: count[k - 1] for k - 1 = u .. n + i
    for (std::size_t k = u + 1; k > n + i; --k) count[k - 1] -= count[k - 1 - (n + i)];
  long double below = 0.0L, total = 1.0L;
  for (const long double c : count) below += c;
  for (std::size_t i = 1; i <= m; ++i)
    total = total * static_cast<long double>(n + i) / static_cast<long double>(i);
  return static_cast<double>(below / total);
}

}  // namespace

MannWhitney mann_whitney(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns) {
  MannWhitney r;
  r.n_a = a_ns.size();
  r.n_b = b_ns.size();
  if (r.n_a == 0 || r.n_b == 0) return r;
  std::vector<std::int64_t> a(a_ns.begin(), a_ns.end()), b(b_ns.begin(), b_ns.end());
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());

  // Walk the tie groups of the pooled sample. A group of ca values from a and cb from b occupying
  // ranks start+1 .. start+t has average rank start + (t + 1) / 2; twice the rank sum of a's members
  // is ca (2 start + t + 1), an integer.
  std::size_t i = 0, j = 0;
  std::uint64_t start = 0;       // values ranked so far
  long double twice_rank_a = 0;  // 2 R_a (exact up to 2^64 in the long double's 64-bit mantissa)
  double tie_term = 0.0;         // sum over groups of t^3 - t
  while (i < a.size() || j < b.size()) {
    const std::int64_t v = (j == b.size() || (i < a.size() && a[i] <= b[j])) ? a[i] : b[j];
    std::uint64_t ca = 0, cb = 0;
    while (i < a.size() && a[i] == v) ++i, ++ca;
    while (j < b.size() && b[j] == v) ++j, ++cb;
    const std::uint64_t t = ca + cb;
    twice_rank_a += static_cast<long double>(ca) * static_cast<long double>(2 * start + t + 1);
    const auto td = static_cast<double>(t);
    tie_term += td * td * td - td;
    start += t;
  }
  const auto na = static_cast<double>(r.n_a), nb = static_cast<double>(r.n_b), n = na + nb;
  const auto twice_u_a = twice_rank_a - static_cast<long double>(r.n_a) * static_cast<long double>(r.n_a + 1);
  r.u_a = static_cast<double>(twice_u_a / 2);
  r.probability_a_greater = r.u_a / (na * nb);
  const double u = std::max(r.u_a, na * nb - r.u_a);
  const double mu = na * nb / 2.0;
  const double variance = na * nb / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)));
  if (!(variance > 0.0)) return r;  // every value equal (or n = 1 + 1 with a tie): no evidence
  r.z = (u - mu - 0.5) / std::sqrt(variance);
  // SciPy's rule: the exact distribution when a sample has at most kExactMaxSize values and there
  // are no ties (tie_term 0). The tail P(U <= min(U_a, U_b)) is summed term by term, so its length
  // is bounded too (a larger tail means a large p, where the normal approximation is close).
  const auto u_min = static_cast<std::size_t>(na * nb - u);
  if (std::min(r.n_a, r.n_b) <= kExactMaxSize && tie_term == 0.0 && u_min < kExactMaxTail) {
    r.exact = true;
    r.p = std::min(1.0, 2.0 * exact_cdf(std::min(r.n_a, r.n_b), std::max(r.n_a, r.n_b), u_min));
  } else {
    r.p = std::min(1.0, 2.0 * normal_sf(r.z));
  }
  return r;
}

}  // namespace m2mlat::stats
