// Threshold shares: strictly above, exact at the boundary, any order of thresholds.
#include "m2mlat/stats/threshold.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "samples.hpp"

using namespace m2mlat::stats;
using namespace std::chrono_literals;

TEST(Threshold, DefaultsAreHumanFactorsLimitsAndOneSecond) {
  const std::vector<m2mlat::core::Duration> expected = {170ms, 300ms, 400ms, 1s};
  EXPECT_EQ(default_thresholds(), expected);
}

TEST(Threshold, AboveMeansStrictlyGreater) {
  // A sample exactly at a threshold is not above it; one nanosecond more is.
  const auto sorted = test::sorted_copy({170'000'000, 170'000'001, 299'999'999, 300'000'000, 300'000'001});
  const std::vector<m2mlat::core::Duration> limits = {170ms, 300ms};
  const std::vector<ThresholdShare> shares = threshold_shares(sorted, limits);
  ASSERT_EQ(shares.size(), 2u);
  EXPECT_EQ(shares[0].threshold, 170ms);
  EXPECT_EQ(shares[0].count_above, 4u);
  EXPECT_DOUBLE_EQ(shares[0].fraction_above, 0.8);
  EXPECT_EQ(shares[1].count_above, 1u);
  EXPECT_DOUBLE_EQ(shares[1].fraction_above, 0.2);
}

TEST(Threshold, KeepsTheCallersOrder) {
  const auto sorted = test::sorted_copy({-5, 1, 2'000'000'000});
  const std::vector<m2mlat::core::Duration> limits = {1s, -10ns, 0ns};
  const std::vector<ThresholdShare> shares = threshold_shares(sorted, limits);
  ASSERT_EQ(shares.size(), 3u);
  EXPECT_EQ(shares[0].count_above, 1u);
  EXPECT_EQ(shares[1].count_above, 3u);
  EXPECT_EQ(shares[2].count_above, 2u);
}

TEST(Threshold, EmptySampleHasNoFraction) {
  const std::vector<ThresholdShare> shares = threshold_shares({}, default_thresholds());
  ASSERT_EQ(shares.size(), 4u);
  for (const ThresholdShare& s : shares) {
    EXPECT_EQ(s.count_above, 0u);
    EXPECT_TRUE(std::isnan(s.fraction_above));
  }
}
