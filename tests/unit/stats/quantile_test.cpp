// Type-7 quantiles: positions, edge probabilities, integer and double inputs, errors.
#include "m2mlat/stats/quantile.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "samples.hpp"

using namespace m2mlat::stats;
using m2mlat::stats::test::expect_close;

TEST(Quantile, PositionIsNMinusOneTimesP) {
  QuantilePosition at = quantile_position(5, 0.5);  // h = 2
  EXPECT_EQ(at.lower, 2u);
  EXPECT_EQ(at.fraction, 0.0);
  at = quantile_position(4, 0.5);  // h = 1.5
  EXPECT_EQ(at.lower, 1u);
  EXPECT_EQ(at.fraction, 0.5);
  at = quantile_position(4, 1.0);  // the last value, nothing to interpolate with
  EXPECT_EQ(at.lower, 3u);
  EXPECT_EQ(at.fraction, 0.0);
  at = quantile_position(1, 0.3);
  EXPECT_EQ(at.lower, 0u);
  EXPECT_EQ(at.fraction, 0.0);
}

TEST(Quantile, EdgesAreMinimumAndMaximum) {
  const std::vector<std::int64_t> v = {-5, 0, 7, 7, 100};
  EXPECT_EQ(quantile(v, 0.0), -5.0);
  EXPECT_EQ(quantile(v, 1.0), 100.0);
  EXPECT_EQ(quantile(v, 0.5), 7.0);
  const std::vector<double> d = {-1.5, 2.25};
  EXPECT_EQ(quantile(d, 0.0), -1.5);
  EXPECT_EQ(quantile(d, 1.0), 2.25);
  EXPECT_EQ(quantile(d, 0.5), 0.375);
}

TEST(Quantile, InterpolatesBetweenNeighbours) {
  // n = 4: h = 3p. p = 0.1 -> h = 0.3, between 10 and 20.
  const std::vector<std::int64_t> v = {10, 20, 40, 80};
  expect_close(quantile(v, 0.1), 13.0);
  expect_close(quantile(v, 0.9), 68.0);  // h = 2.7: 40 + 0.7 * 40
  // Interpolation from b's side for t >= 0.5 hits b exactly at t = 1 and stays monotone.
  EXPECT_EQ(interpolate(0.1, 0.7, 1.0), 0.7);
  EXPECT_EQ(interpolate(0.1, 0.7, 0.0), 0.1);
  EXPECT_EQ(interpolate(std::int64_t{3}, std::int64_t{5}, 0.5), 4.0);
}

TEST(Quantile, HugeSpreadDoesNotOverflow) {
  // The difference of the neighbours exceeds int64; it is taken in uint64.
  const std::int64_t lo = std::numeric_limits<std::int64_t>::min(),
                     hi = std::numeric_limits<std::int64_t>::max();
  const std::vector<std::int64_t> v = {lo, hi};
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.25), -4611686018427387904.0);
}

TEST(Quantile, EmptyIsNaN) {
  EXPECT_TRUE(std::isnan(quantile(std::vector<std::int64_t>{}, 0.5)));
  EXPECT_TRUE(std::isnan(quantile(std::vector<double>{}, 0.5)));
}

TEST(Quantile, ProbabilityOutsideUnitIntervalIsAUsageError) {
  const std::vector<std::int64_t> v = {1, 2, 3};
  for (const double p : {-0.01, 1.0000001, std::numeric_limits<double>::quiet_NaN()}) {
    try {
      (void)quantile(v, p);
      ADD_FAILURE() << "no error for p = " << p;
    } catch (const m2mlat::core::Error& e) {
      EXPECT_EQ(e.kind(), m2mlat::core::ErrorKind::usage);
    }
  }
  EXPECT_THROW((void)quantile_position(0, 0.5), m2mlat::core::Error);
}
