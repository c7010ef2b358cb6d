// A resample's order statistics drawn directly: the distribution of each against its exact
// binomial form, jointly against resamples drawn and sorted the slow way, the variates' moments,
// and the exact values of the Python implementation.
#include "m2mlat/stats/order_statistics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "m2mlat/stats/rng.hpp"

using namespace m2mlat::stats;

namespace {

// P(Binomial(n, p) >= k), summed term by term (n small).
double binomial_at_least(std::size_t n, double p, std::size_t k) {
  double total = 0.0;
  for (std::size_t i = k; i <= n; ++i) {
    double term = std::pow(p, static_cast<double>(i)) * std::pow(1.0 - p, static_cast<double>(n - i));
    for (std::size_t j = 0; j < i; ++j)
      term *= static_cast<double>(n - j) / static_cast<double>(i - j);  // n choose i, built up
    total += term;
  }
  return total;
}

// The largest distance between two empirical distribution functions of integers (two-sample
// Kolmogorov-Smirnov statistic).
double ks_distance(std::vector<std::int64_t> a, std::vector<std::int64_t> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double d = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const std::int64_t x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] == x) ++i;
    while (j < b.size() && b[j] == x) ++j;
    d = std::max(d, std::fabs(static_cast<double>(i) / static_cast<double>(a.size()) -
                              static_cast<double>(j) / static_cast<double>(b.size())));
  }
  return d;
}

}  // namespace

TEST(OrderStatistics, EachHasTheBinomialDistributionOfAResample) {
  // The j-th smallest of n ranks is <= r exactly when at least j + 1 of the n draws are <= r:
  // P = P(Binomial(n, (r + 1) / n) >= j + 1). 100,000 resamples of n = 25; with the fixed seed the
  // result is the same every run, and a sampler off by one rank in 2 % of resamples would exceed
  // the bound (1.95 / sqrt(100,000) = 0.0062, the Kolmogorov-Smirnov test's 0.1 % level; with 10^6
  // resamples the largest distance was 0.0008).
  constexpr std::size_t n = 25, draws = 100'000;
  const std::vector<std::size_t> wanted = {0, 6, 12, 13, 18, 24};
  std::vector<std::vector<std::size_t>> counts(wanted.size(), std::vector<std::size_t>(n, 0));
  std::vector<std::size_t> ranks(wanted.size());
  for (std::size_t b = 0; b < draws; ++b) {
    Rng rng = Rng::stream(41, b);
    resample_order_statistics(rng, n, wanted, ranks);
    for (std::size_t i = 0; i < wanted.size(); ++i) {
      ASSERT_LT(ranks[i], n);
      if (i > 0) {
        ASSERT_LE(ranks[i - 1], ranks[i]);
      }
      ++counts[i][ranks[i]];
    }
  }
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    double cumulative = 0.0, worst = 0.0;
    for (std::size_t r = 0; r < n; ++r) {
      cumulative += static_cast<double>(counts[i][r]) / draws;
      const double exact = binomial_at_least(n, static_cast<double>(r + 1) / n, wanted[i] + 1);
      worst = std::max(worst, std::fabs(cumulative - exact));
    }
    EXPECT_LT(worst, 0.0062) << "order statistic " << wanted[i];
  }
}

TEST(OrderStatistics, JointlyTheyAreThoseOfResamplesDrawnAndSorted) {
  // The interquartile range in ranks (q3's order statistic minus q1's) depends on both jointly:
  // its distribution equals that of resamples drawn rank by rank and sorted.
  constexpr std::size_t n = 41, draws = 100'000;
  const std::vector<std::size_t> wanted = {10, 20, 30};
  std::vector<std::int64_t> direct, sorted_spread, direct_sum, sorted_sum;
  std::vector<std::size_t> ranks(wanted.size());
  std::vector<std::uint32_t> resample(n);
  for (std::size_t b = 0; b < draws; ++b) {
    Rng rng = Rng::stream(5, b);
    resample_order_statistics(rng, n, wanted, ranks);
    direct.push_back(static_cast<std::int64_t>(ranks[2] - ranks[0]));
    direct_sum.push_back(static_cast<std::int64_t>(ranks[0] + ranks[1] + ranks[2]));
    IndexStream draw(Rng::stream(6, b), n);
    for (std::uint32_t& r : resample) r = draw.next();
    std::sort(resample.begin(), resample.end());
    sorted_spread.push_back(static_cast<std::int64_t>(resample[30]) - resample[10]);
    sorted_sum.push_back(static_cast<std::int64_t>(resample[10]) + resample[20] + resample[30]);
  }
  // Two samples of 100,000: 1.95 sqrt(2 / 100,000) = 0.0087 at the 0.1 % level (10^6 each: 0.0011).
  EXPECT_LT(ks_distance(direct, sorted_spread), 0.0087);
  EXPECT_LT(ks_distance(direct_sum, sorted_sum), 0.0087);
}

TEST(OrderStatistics, SmallestSamples) {
  std::vector<std::size_t> one(1);
  Rng rng = Rng::stream(1, 0);
  for (int i = 0; i < 100; ++i) {
    resample_order_statistics(rng, 1, std::vector<std::size_t>{0}, one);
    ASSERT_EQ(one[0], 0u);
  }
  // n = 2, both order statistics: (0, 0), (0, 1), (1, 1) with probabilities 1/4, 1/2, 1/4.
  std::vector<std::size_t> two(2);
  double both_low = 0, split = 0, both_high = 0;
  for (int i = 0; i < 8000; ++i) {
    resample_order_statistics(rng, 2, std::vector<std::size_t>{0, 1}, two);
    if (two[1] == 0)
      ++both_low;
    else if (two[0] == 0)
      ++split;
    else
      ++both_high;
  }
  EXPECT_NEAR(both_low / 8000.0, 0.25, 0.02);
  EXPECT_NEAR(split / 8000.0, 0.5, 0.02);
  EXPECT_NEAR(both_high / 8000.0, 0.25, 0.02);
}

TEST(OrderStatistics, TheMedianOfTenMillion) {
  // Rank of a resample's median: mean n / 2, standard deviation sqrt(n) / 2 (1581 for 10^7).
  constexpr std::size_t n = 10'000'000, draws = 4000;
  std::vector<std::size_t> rank(1);
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t b = 0; b < draws; ++b) {
    Rng rng = Rng::stream(77, b);
    resample_order_statistics(rng, n, std::vector<std::size_t>{n / 2}, rank);
    const double d = static_cast<double>(rank[0]) - static_cast<double>(n / 2);
    sum += d;
    sum2 += d * d;
  }
  const double mean = sum / draws, sd = std::sqrt(sum2 / draws - mean * mean);
  EXPECT_LT(std::fabs(mean), 4 * 1581.1 / std::sqrt(static_cast<double>(draws)));
  EXPECT_NEAR(sd, 1581.1, 0.05 * 1581.1);
}

TEST(OrderStatistics, VariatesHaveTheirMoments) {
  Rng rng = Rng::stream(3, 0);
  constexpr int draws = 40'000;
  for (const double shape : {1.0, 2.0, 7.0, 1e6}) {
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < draws; ++i) {
      const double g = gamma_variate(rng, shape);
      ASSERT_GT(g, 0.0);
      sum += g;
      sum2 += g * g;
    }
    const double mean = sum / draws, var = sum2 / draws - mean * mean;
    // Gamma(k): mean k, variance k.
    EXPECT_NEAR(mean, shape, 4 * std::sqrt(shape / draws)) << shape;
    EXPECT_NEAR(var, shape, 0.05 * shape) << shape;
  }
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < draws; ++i) {
    const double z = normal_variate(rng);
    sum += z;
    sum2 += z * z;
  }
  EXPECT_NEAR(sum / draws, 0.0, 0.02);
  EXPECT_NEAR(sum2 / draws, 1.0, 0.03);
}

TEST(OrderStatistics, MatchIndependentPythonImplementation) {
  // reference_values.py: "Order statistics of a resample", operation by operation in Python floats.
  Rng normal = Rng::stream(9, 0);
  EXPECT_EQ(normal_variate(normal), -0.6305639223177938);
  Rng gamma = Rng::stream(9, 1);
  EXPECT_EQ(gamma_variate(gamma, 1.0), 2.1436215163797465);
  EXPECT_EQ(gamma_variate(gamma, 1e6), 1001251.2456325071);
  std::vector<std::size_t> ranks(3);
  Rng rng = Rng::stream(2024, 0);
  resample_order_statistics(rng, 10'007, std::vector<std::size_t>{2501, 2502, 5003}, ranks);
  EXPECT_EQ(ranks, (std::vector<std::size_t>{2566, 2567, 5060}));
}
