// Mean and standard deviation: exactness where naive double sums fail.
#include "m2mlat/stats/moments.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "m2mlat/core/error.hpp"

using namespace m2mlat::stats;

TEST(Moments, TenMillionSamplesNearOneSecond) {
  // 10^4 copies of 1e9 + k for k = 0..999: the mean is 1e9 + 499.5 exactly, and the sample
  // variance is the population variance of 0..999, (1000^2 - 1)/12, times n/(n - 1).
  const std::size_t n = 10'000'000;
  std::vector<std::int64_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = 1'000'000'000 + static_cast<std::int64_t>(i % 1000);
  const Mean m = exact_mean(v);
  EXPECT_EQ(m.floor_ns, 1'000'000'499);
  EXPECT_EQ(m.fraction, 0.5);
  EXPECT_EQ(m.mean, 1'000'000'499.5);
  const double expected_sd = std::sqrt(83333.25 * static_cast<double>(n) / static_cast<double>(n - 1));
  EXPECT_NEAR(sample_sd(v, m), expected_sd, 1e-12 * expected_sd);
}

TEST(Moments, SumsBeyondInt64AreExact) {
  // reference_values.py: near_max, near_min (Python's integers divide exactly).
  const std::int64_t max = std::numeric_limits<std::int64_t>::max(),
                     min = std::numeric_limits<std::int64_t>::min();
  const std::vector<std::int64_t> high = {max, max, max - 1};
  Mean m = exact_mean(high);
  EXPECT_EQ(m.floor_ns, 9223372036854775806);
  EXPECT_DOUBLE_EQ(m.fraction, 2.0 / 3.0);
  EXPECT_EQ(m.mean, 9.223372036854776e+18);

  const std::vector<std::int64_t> low = {min, min, -1};
  m = exact_mean(low);
  EXPECT_EQ(m.floor_ns, -6148914691236517206);
  EXPECT_DOUBLE_EQ(m.fraction, 1.0 / 3.0);
  EXPECT_EQ(m.mean, -6.148914691236517e+18);
}

TEST(Moments, ExactSumDivision) {
  ExactSum s;
  for (int i = 0; i < 7; ++i) s.add(-1);  // -7 = -3 * 3 + 2
  const ExactSum::Division d = s.divide(3);
  EXPECT_EQ(d.quotient, -3);
  EXPECT_EQ(d.remainder, 2u);
  EXPECT_THROW((void)s.divide(0), m2mlat::core::Error);
  ExactSum zero;
  EXPECT_EQ(zero.divide(5).quotient, 0);
  EXPECT_EQ(zero.divide(5).remainder, 0u);
}

TEST(Moments, StandardDeviationFarFromZero) {
  // Deviations are taken in integers, so an offset of 1e18 (where doubles are 128 apart) does no
  // harm. reference_values.py: far_offset.sd_ns (statistics.stdev, exact).
  const std::int64_t base = 1'000'000'000'000'000'000;
  const std::vector<std::int64_t> v = {base, base + 1, base + 2, base + 3};
  EXPECT_DOUBLE_EQ(sample_sd(v, exact_mean(v)), 1.2909944487358056);
}

TEST(Moments, SpreadBeyondInt64FallsBackToDoubles) {
  const std::int64_t max = std::numeric_limits<std::int64_t>::max(),
                     min = std::numeric_limits<std::int64_t>::min();
  const std::vector<std::int64_t> v = {min, max};
  // Mean -0.5; sd of {-2^63, 2^63 - 1} is (2^64 - 1)/sqrt(2), which doubles give as 2^64/sqrt(2).
  const Mean m = exact_mean(v);
  EXPECT_EQ(m.mean, -0.5);
  EXPECT_DOUBLE_EQ(sample_sd(v, m), 18446744073709551616.0 / std::sqrt(2.0));
}

TEST(Moments, SmallSamples) {
  EXPECT_TRUE(std::isnan(exact_mean(std::vector<std::int64_t>{}).mean));
  const std::vector<std::int64_t> one = {42};
  EXPECT_EQ(exact_mean(one).mean, 42.0);
  EXPECT_TRUE(std::isnan(sample_sd(one, exact_mean(one))));
  const std::vector<std::int64_t> two = {-3, 4};
  EXPECT_EQ(exact_mean(two).mean, 0.5);
  EXPECT_DOUBLE_EQ(sample_sd(two, exact_mean(two)), 7.0 / std::sqrt(2.0));
}
