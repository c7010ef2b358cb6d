// Samples and a tolerance shared by the statistics tests. The reference values for these
// samples come from reference_values.py (numpy and Python's statistics module).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace m2mlat::stats::test {

// Latencies from Knuth's MMIX LCG: 120 ms plus 0..899.999999 ms, ns. reference_values.py has
// the same generator (lcg_sample), so the sample need not be stored.
inline std::vector<std::int64_t> lcg_sample(std::size_t n, std::uint64_t seed) {
  std::vector<std::int64_t> out;
  out.reserve(n);
  std::uint64_t state = seed;
  for (std::size_t i = 0; i < n; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    out.push_back(120'000'000 + static_cast<std::int64_t>((state >> 33) % 900'000'000));
  }
  return out;
}

inline std::vector<std::int64_t> sorted_copy(std::vector<std::int64_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// Agreement with numpy to a few units in the last place: the C++ code follows numpy's formulas,
// but a compiler may fuse a multiply and an add where numpy does not.
inline void expect_close(double actual, double expected) {
  if (std::isnan(expected)) {
    EXPECT_TRUE(std::isnan(actual)) << actual;
    return;
  }
  EXPECT_NEAR(actual, expected, 1e-13 * std::max(std::fabs(expected), 1e-3)) << "expected " << expected;
}

}  // namespace m2mlat::stats::test
