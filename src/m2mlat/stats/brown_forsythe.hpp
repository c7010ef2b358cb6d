// Brown-Forsythe test for equal spread: Levene's test on absolute deviations from each group's
// median, robust to the skewed, long-tailed distributions latencies have.
//
// Definition (as scipy.stats.levene with center="median"): for k groups with n_i values y_ij,
// z_ij = |y_ij - median_i| (type-7 median); W = (N - k) / (k - 1) * sum_i n_i (zbar_i - zbar)^2 /
// sum_ij (z_ij - zbar_i)^2 with zbar_i the group means of z and zbar the overall mean; under equal
// spread W follows F(k - 1, N - k), so p = P(F > W).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace m2mlat::stats {

struct BrownForsythe {
  double w = 0.0;    // the statistic
  double df1 = 0.0;  // k - 1
  double df2 = 0.0;  // N - k
  double p = 1.0;    // P(F(df1, df2) > w); 1 when undefined (fewer than 2 groups with values, N <= k,
                     // or no spread in any group)
};

// Groups of latencies in ns (any order). Empty groups are ignored.
BrownForsythe brown_forsythe(std::span<const std::span<const std::int64_t>> groups_ns);
BrownForsythe brown_forsythe(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns);

}  // namespace m2mlat::stats
