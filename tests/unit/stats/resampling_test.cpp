// The bootstrap's resampling plan (units, blocks: block_length.hpp) and the resampling of units.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/block_length.hpp"
#include "m2mlat/stats/bootstrap.hpp"
#include "m2mlat/stats/rng.hpp"

using namespace m2mlat::stats;

namespace {

// An AR(1) series x_t = phi x_{t-1} + e_t with uniform innovations (ns around 1 s).
std::vector<std::int64_t> ar1(std::size_t n, double phi, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<std::int64_t> out;
  double x = 0;
  for (std::size_t t = 0; t < n; ++t) {
    x = phi * x + (rng.uniform01() - 0.5) * 1e8;
    out.push_back(1'000'000'000 + static_cast<std::int64_t>(x));
  }
  return out;
}

std::vector<double> as_doubles(const std::vector<std::int64_t>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST(BlockLength, IndependentSeriesNeedNoBlocks) {
  int blocked = 0;
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    const BlockLength b = block_length(as_doubles(ar1(500, 0.0, seed)));
    blocked += b.length > 1 ? 1 : 0;
    EXPECT_LT(std::fabs(b.lag1), 0.2);
  }
  EXPECT_LE(blocked, 5);  // the screen's false alarms: about 3 % of independent series of 500
  EXPECT_EQ(block_length(std::vector<double>(100, 3.0)).length, 1u);
  EXPECT_EQ(block_length(std::vector<double>{1, 2, 3}).length, 1u);
}

TEST(BlockLength, CorrelatedSeriesGetLongerBlocksTheFurtherTheCorrelationReaches) {
  const BlockLength mild = block_length(as_doubles(ar1(2000, 0.5, 7)));
  const BlockLength strong = block_length(as_doubles(ar1(2000, 0.9, 7)));
  EXPECT_NEAR(mild.lag1, 0.5, 0.06);
  EXPECT_NEAR(strong.lag1, 0.9, 0.03);
  EXPECT_GT(mild.length, 1u);
  EXPECT_GT(strong.length, mild.length);
  EXPECT_GT(strong.reach, mild.reach);
  // Politis and White's optimal block for an AR(1) with phi = 0.9 at n = 2000 is about 40 values.
  EXPECT_GT(strong.length, 15u);
  EXPECT_LT(strong.length, 90u);
}

TEST(BlockLength, ALongSeriesIsEstimatedFromStretches) {
  const auto stretches = estimation_stretches(std::size_t{1} << 22);
  ASSERT_EQ(stretches.size(), 16u);
  EXPECT_EQ(stretches.front().begin, 0u);
  EXPECT_EQ(stretches.back().end, std::size_t{1} << 22);
  const BlockLength b = block_length(as_doubles(ar1(std::size_t{1} << 19, 0.7, 3)));
  EXPECT_EQ(b.used, std::size_t{1} << 18);
  EXPECT_NEAR(b.lag1, 0.7, 0.02);
}

TEST(Resampling, PlanCountsTheUnitsAndRefusesStartsOutOfOrder) {
  const auto x = ar1(10, 0.0, 1);
  const std::vector<std::size_t> starts{0, 3, 4, 8};
  const Resampling plan = plan_resampling(x, starts);
  EXPECT_EQ(plan.samples, 10u);
  EXPECT_EQ(plan.units, 4u);
  EXPECT_EQ(plan.largest_unit, 4u);
  EXPECT_TRUE(plan.grouped());
  EXPECT_FALSE(plan.sample_by_sample());
  const Resampling single = plan_resampling(x, {});
  EXPECT_EQ(single.units, 10u);
  EXPECT_TRUE(single.sample_by_sample());
  for (const std::vector<std::size_t>& bad : {std::vector<std::size_t>{1, 3}, std::vector<std::size_t>{0, 3, 3},
                                              std::vector<std::size_t>{0, 10}, std::vector<std::size_t>{0, 5, 2}})
    EXPECT_THROW((void)plan_resampling(x, bad), m2mlat::core::Error);
}

TEST(Resampling, ASampleBySamplePlanGivesThePlainBootstrapExactly) {
  auto x = ar1(300, 0.0, 11);
  const Resampling plan = plan_resampling(x, {});
  ASSERT_TRUE(plan.sample_by_sample());
  const auto ci = resample_median_iqr(x, {}, plan, {500, 4, 0.95});
  std::sort(x.begin(), x.end());
  const auto plain = bootstrap_median_iqr(x, {500, 4, 0.95});
  ASSERT_TRUE(ci && plain);
  EXPECT_EQ(ci->median_ms.lower, plain->median_ms.lower);
  EXPECT_EQ(ci->median_ms.upper, plain->median_ms.upper);
  EXPECT_EQ(ci->iqr_ms.upper, plain->iqr_ms.upper);
  EXPECT_EQ(ci->resampling.units, 300u);
}

TEST(Resampling, UnitsOfCopiesAreAsWideAsTheirValuesAloneAndPairsAreNot) {
  // 100 manoeuvres of 9 pairs with the same latency: 100 values' worth of information, not 900.
  const auto values = ar1(100, 0.0, 5);
  std::vector<std::int64_t> copies;
  std::vector<std::size_t> starts;
  for (const auto v : values) {
    starts.push_back(copies.size());
    copies.insert(copies.end(), 9, v);
  }
  const BootstrapOptions options{2000, 9, 0.95};
  const auto by_units = resample_median_iqr(copies, starts, plan_resampling(copies, starts), options);
  auto sorted_values = values;
  std::sort(sorted_values.begin(), sorted_values.end());
  const auto alone = bootstrap_median_iqr(sorted_values, options);
  auto sorted_copies = copies;
  std::sort(sorted_copies.begin(), sorted_copies.end());
  const auto by_pairs = bootstrap_median_iqr(sorted_copies, options);
  ASSERT_TRUE(by_units && alone && by_pairs);
  EXPECT_TRUE(by_units->resampling.grouped());
  EXPECT_NEAR(by_units->median_ms.width() / alone->median_ms.width(), 1.0, 0.2);
  EXPECT_LT(by_pairs->median_ms.width() / alone->median_ms.width(), 0.5);  // about 1/3: sqrt(1/9)
  // The same seed, the same intervals.
  const auto again = resample_median_iqr(copies, starts, by_units->resampling, options);
  EXPECT_EQ(again->median_ms.lower, by_units->median_ms.lower);
  EXPECT_EQ(again->iqr_ms.upper, by_units->iqr_ms.upper);
}

TEST(Resampling, CorrelatedSamplesAreResampledInBlocksAndWidenTheInterval) {
  const auto x = ar1(1000, 0.8, 21);
  const Resampling plan = plan_resampling(x, {});
  EXPECT_FALSE(plan.grouped());
  EXPECT_GT(plan.blocks.length, 3u);
  const BootstrapOptions options{1000, 2, 0.95};
  const auto blocks = resample_median_iqr(x, {}, plan, options);
  auto sorted = x;
  std::sort(sorted.begin(), sorted.end());
  const auto plain = bootstrap_median_iqr(sorted, options);
  // An AR(1) with phi = 0.8 has a long-run variance (1 + phi) / (1 - phi) = 9 times its variance.
  EXPECT_GT(blocks->median_ms.width(), 2.0 * plain->median_ms.width());
}

TEST(Resampling, AboveTheLimitGroupedSamplesAreResampledOneByOneAndSaySo) {
  std::vector<std::int64_t> x(kMaxUnitResampled + 2, 5);
  const Resampling plan = plan_resampling(x, std::vector<std::size_t>{0, 2});
  EXPECT_TRUE(plan.over_limit);
  EXPECT_TRUE(plan.sample_by_sample());
}
