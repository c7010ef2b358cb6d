// Bootstrap: exact agreement with a slow, obvious implementation (here and in Python),
// reproducibility, and the statistical behaviour of the intervals.
#include "m2mlat/stats/bootstrap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/rng.hpp"
#include "samples.hpp"

using namespace m2mlat::stats;
using m2mlat::stats::test::expect_close;
using m2mlat::stats::test::lcg_sample;
using m2mlat::stats::test::sorted_copy;

namespace {

// The definition in bootstrap.hpp done the slow way: draw n indices, sort the resample, take
// its quantiles.
std::vector<double> naive_resample_quantiles(const std::vector<std::int64_t>& sorted,
                                             const std::vector<double>& probabilities, std::uint64_t seed,
                                             std::size_t b) {
  IndexStream draw(Rng::stream(seed, b), static_cast<std::uint32_t>(sorted.size()));
  std::vector<std::int64_t> resample(sorted.size());
  for (std::int64_t& x : resample) x = sorted[draw.next()];
  std::sort(resample.begin(), resample.end());
  std::vector<double> out;
  for (const double p : probabilities) out.push_back(quantile(resample, p));
  return out;
}

// Latencies whose true median and quartiles are known: the smaller of two uniform integers in
// [0, 2^30). P(min <= x) = 1 - (1 - x/M)^2, so the p-quantile is M (1 - sqrt(1 - p)).
constexpr double kM = 1073741824.0;
std::vector<std::int64_t> min_of_two_uniforms(Rng& rng, std::size_t n) {
  std::vector<std::int64_t> v(n);
  for (std::int64_t& x : v) {
    x = static_cast<std::int64_t>(std::min(rng.below(1ULL << 30), rng.below(1ULL << 30)));
  }
  std::sort(v.begin(), v.end());
  return v;
}
double true_quantile(double p) { return kM * (1.0 - std::sqrt(1.0 - p)); }

}  // namespace

TEST(Bootstrap, CountingEqualsSortingEachResample) {
  const std::vector<double> probs = {0.25, 0.5, 0.75, 0.0, 1.0, 0.975};
  for (const std::size_t n : {1u, 2u, 7u, 100u, 1001u}) {
    const auto sorted = sorted_copy(lcg_sample(n, 31 + n));
    const BootstrapQuantiles q = bootstrap_quantiles(sorted, probs, 40, 9);
    ASSERT_EQ(q.resamples, 40u);
    for (std::size_t b = 0; b < q.resamples; ++b) {
      const std::vector<double> expected = naive_resample_quantiles(sorted, probs, 9, b);
      for (std::size_t k = 0; k < probs.size(); ++k)
        ASSERT_EQ(q.value(b, k), expected[k]) << n << " " << b << " " << k;
    }
  }
}

TEST(Bootstrap, WindowedCountingEqualsFullCounting) {
  // Windowed counting is chosen automatically for large samples; forced here on a small one, once
  // with the default windows and once with windows so narrow that resamples miss them and are
  // counted again in full.
  const auto sorted = sorted_copy(lcg_sample(20'000, 77));
  const std::vector<double> probs = {0.25, 0.5, 0.75, 0.05, 0.99};
  using detail::RankCounting;
  const BootstrapQuantiles full = detail::bootstrap_quantiles(sorted, probs, 60, 5, RankCounting::full);
  std::size_t fallbacks = 99;
  const BootstrapQuantiles windowed =
      detail::bootstrap_quantiles(sorted, probs, 60, 5, RankCounting::windowed, 0, &fallbacks);
  EXPECT_EQ(fallbacks, 0u);
  EXPECT_EQ(windowed.values, full.values);
  const BootstrapQuantiles narrow =
      detail::bootstrap_quantiles(sorted, probs, 60, 5, RankCounting::windowed, 20, &fallbacks);
  EXPECT_GT(fallbacks, 10u);
  EXPECT_EQ(narrow.values, full.values);
}

TEST(Bootstrap, TheNumberOfThreadsChangesNothing) {
  // Each resample draws from its own stream, so sharing them among threads (unevenly: 61
  // resamples among 2 and 3) gives the same values, and the same fallbacks in total.
  const auto sorted = sorted_copy(lcg_sample(20'000, 78));
  const std::vector<double> probs = {0.25, 0.5, 0.75, 0.99};
  using detail::RankCounting;
  std::size_t one_fallbacks = 0;
  const BootstrapQuantiles one =
      detail::bootstrap_quantiles(sorted, probs, 61, 6, RankCounting::windowed, 20, &one_fallbacks, 1);
  EXPECT_GT(one_fallbacks, 10u);
  for (const std::size_t threads : {2u, 3u, 100u}) {
    std::size_t fallbacks = 0;
    const BootstrapQuantiles many =
        detail::bootstrap_quantiles(sorted, probs, 61, 6, RankCounting::windowed, 20, &fallbacks, threads);
    EXPECT_EQ(many.values, one.values) << threads;
    EXPECT_EQ(fallbacks, one_fallbacks) << threads;
  }
  EXPECT_EQ(detail::bootstrap_threads(20'000, 61), 1u);  // 1.2 M draws: one thread
  // 2e10 draws: one thread a core, at most four.
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  EXPECT_EQ(detail::bootstrap_threads(10'000'000, 2000), std::min(cores, detail::kMaxBootstrapThreads));
}

TEST(Bootstrap, MatchesIndependentPythonImplementation) {
  // reference_values.py: "Bootstrap of lcg_sample(25, 7), B = 300, seed = 2024, level 0.95",
  // computed by drawing with a Python xoshiro256**, sorting, and numpy.percentile.
  const auto sorted = sorted_copy(lcg_sample(25, 7));
  const std::vector<double> probs = {0.25, 0.5, 0.75};
  const BootstrapQuantiles q = bootstrap_quantiles(sorted, probs, 300, 2024);
  EXPECT_EQ(q.value(0, 1), 417257219.0);
  EXPECT_EQ(q.value(1, 1), 566905654.0);
  EXPECT_EQ(q.value(2, 1), 456694899.0);
  EXPECT_EQ(q.column(1).size(), 300u);
  EXPECT_EQ(q.column(1)[2], 456694899.0);
  EXPECT_EQ(q.value(0, 2) - q.value(0, 0), 317886527.0);
  EXPECT_EQ(q.value(1, 2) - q.value(1, 0), 319782314.0);
  const auto ci = bootstrap_median_iqr(sorted, {300, 2024, 0.95});
  ASSERT_TRUE(ci);
  expect_close(ci->median_ms.lower, 381.473951);
  expect_close(ci->median_ms.upper, 584.74328);
  expect_close(ci->iqr_ms.lower, 164.55837805000002);
  expect_close(ci->iqr_ms.upper, 517.059842);
}

TEST(Bootstrap, SameSeedSameIntervalsOtherSeedOtherIntervals) {
  const auto sorted = sorted_copy(lcg_sample(2000, 3));
  const auto a = bootstrap_median_iqr(sorted, {400, 17, 0.95});
  const auto b = bootstrap_median_iqr(sorted, {400, 17, 0.95});
  const auto c = bootstrap_median_iqr(sorted, {400, 18, 0.95});
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->median_ms.lower, b->median_ms.lower);
  EXPECT_EQ(a->median_ms.upper, b->median_ms.upper);
  EXPECT_EQ(a->iqr_ms.lower, b->iqr_ms.lower);
  EXPECT_EQ(a->iqr_ms.upper, b->iqr_ms.upper);
  EXPECT_TRUE(a->median_ms.lower != c->median_ms.lower || a->median_ms.upper != c->median_ms.upper);
  EXPECT_TRUE(a->iqr_ms.lower != c->iqr_ms.lower || a->iqr_ms.upper != c->iqr_ms.upper);
  const std::vector<double> probs = {0.5};
  EXPECT_EQ(bootstrap_quantiles(sorted, probs, 50, 17).values,
            bootstrap_quantiles(sorted, probs, 50, 17).values);
  EXPECT_NE(bootstrap_quantiles(sorted, probs, 50, 17).values,
            bootstrap_quantiles(sorted, probs, 50, 18).values);
}

TEST(Bootstrap, IntervalContainsTheSampleStatistic) {
  for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
    const auto sorted = sorted_copy(lcg_sample(101 + 50 * seed, seed));
    const auto ci = bootstrap_median_iqr(sorted, {1000, seed, 0.95});
    ASSERT_TRUE(ci);
    const double median_ms = quantile(sorted, 0.5) / 1e6;
    const double iqr_ms = (quantile(sorted, 0.75) - quantile(sorted, 0.25)) / 1e6;
    EXPECT_TRUE(ci->median_ms.contains(median_ms)) << seed;
    EXPECT_TRUE(ci->iqr_ms.contains(iqr_ms)) << seed;
    EXPECT_GT(ci->median_ms.width(), 0.0);
  }
}

TEST(Bootstrap, WidthShrinksAsOneOverSquareRootOfN) {
  // 16 times the samples: intervals about 4 times narrower. Averaged over 8 samples each, as a
  // single median interval is noisy (it is set by a few order statistics).
  Rng rng(12345);
  const auto mean_width = [&](std::size_t n) {
    double sum = 0;
    for (int i = 0; i < 8; ++i) {
      const auto sorted = min_of_two_uniforms(rng, n);
      sum += bootstrap_median_iqr(sorted, {500, static_cast<std::uint64_t>(i), 0.95})->median_ms.width();
    }
    return sum / 8;
  };
  const double ratio = mean_width(500) / mean_width(8000);
  EXPECT_GT(ratio, 3.2);
  EXPECT_LT(ratio, 5.0);
}

TEST(Bootstrap, CoversTheTrueMedianAboutNinetyFivePercentOfTheTime) {
  // 1000 experiments: draw 300 latencies from a skewed distribution with a known median and
  // IQR, bootstrap 95 % intervals, count how often they contain the true values. With true
  // coverage 0.95 the count has standard deviation 6.9; percentile intervals for quantiles are
  // known to run slightly under or over at this n, hence the band [0.92, 0.98].
  Rng rng(2718);
  const double true_median_ms = true_quantile(0.5) / 1e6;
  const double true_iqr_ms = (true_quantile(0.75) - true_quantile(0.25)) / 1e6;
  int median_hits = 0, iqr_hits = 0;
  const int experiments = 1000;
  for (int e = 0; e < experiments; ++e) {
    const auto sorted = min_of_two_uniforms(rng, 300);
    const auto ci = bootstrap_median_iqr(sorted, {400, 1000 + static_cast<std::uint64_t>(e), 0.95});
    median_hits += ci->median_ms.contains(true_median_ms) ? 1 : 0;
    iqr_hits += ci->iqr_ms.contains(true_iqr_ms) ? 1 : 0;
  }
  const double median_coverage = median_hits / static_cast<double>(experiments);
  const double iqr_coverage = iqr_hits / static_cast<double>(experiments);
  EXPECT_GT(median_coverage, 0.92);
  EXPECT_LT(median_coverage, 0.98);
  EXPECT_GT(iqr_coverage, 0.92);
  EXPECT_LT(iqr_coverage, 0.98);
  RecordProperty("median_coverage", std::to_string(median_coverage));
  RecordProperty("iqr_coverage", std::to_string(iqr_coverage));
}

TEST(Bootstrap, PercentileIntervalIsType7OfTheReplicates) {
  // 0..100: the 2.5 % and 97.5 % type-7 quantiles are 2.5 and 97.5.
  std::vector<double> r;
  for (int i = 100; i >= 0; --i) r.push_back(i);
  const Interval i = percentile_interval(r, 0.95);
  EXPECT_NEAR(i.lower, 2.5, 1e-12);
  EXPECT_NEAR(i.upper, 97.5, 1e-12);
  EXPECT_NEAR(i.width(), 95.0, 1e-12);
}

TEST(Bootstrap, DegenerateAndInvalidInputs) {
  EXPECT_FALSE(bootstrap_median_iqr({}, {}));
  const std::vector<std::int64_t> one = {5'000'000};
  EXPECT_FALSE(bootstrap_median_iqr(one, {0, 1, 0.95}));
  const auto ci = bootstrap_median_iqr(one, {50, 1, 0.95});
  ASSERT_TRUE(ci);
  EXPECT_EQ(ci->median_ms.lower, 5.0);
  EXPECT_EQ(ci->median_ms.upper, 5.0);
  EXPECT_EQ(ci->iqr_ms.width(), 0.0);

  const std::vector<std::int64_t> unsorted = {3, 1, 2};
  const std::vector<double> half = {0.5};
  EXPECT_THROW((void)bootstrap_quantiles(unsorted, half, 10, 1), m2mlat::core::Error);
  EXPECT_THROW((void)bootstrap_quantiles({}, half, 10, 1), m2mlat::core::Error);
  const std::vector<double> bad = {1.5};
  EXPECT_THROW((void)bootstrap_quantiles(one, bad, 10, 1), m2mlat::core::Error);
  for (const double level : {0.0, 1.0, -0.5, std::nan("")}) {
    EXPECT_THROW((void)bootstrap_median_iqr(one, {10, 1, level}), m2mlat::core::Error) << level;
  }
  EXPECT_THROW((void)percentile_interval({}, 0.95), m2mlat::core::Error);
}
