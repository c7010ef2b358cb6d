// Two-sample comparisons: Mann-Whitney, Brown-Forsythe, the distributions behind them and Newcombe's
// interval against SciPy's values (printed by compare_reference.py), and the bootstrap intervals of
// differences and ratios by their properties.
#include "m2mlat/stats/compare.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/brown_forsythe.hpp"
#include "m2mlat/stats/distributions.hpp"
#include "m2mlat/stats/mann_whitney.hpp"

namespace m2mlat::stats {
namespace {

using namespace std::chrono_literals;

// The samples of compare_reference.py.
std::vector<std::int64_t> sample_a() {
  std::vector<std::int64_t> v;
  for (std::int64_t i = 0; i < 31; ++i) v.push_back(812'000'000 + ((i * 7'919'003) % 97) * 3'000'000);
  v.push_back(812'000'000);
  v.push_back(1'305'000'000);
  return v;
}
std::vector<std::int64_t> sample_b() {
  std::vector<std::int64_t> v;
  for (std::int64_t i = 0; i < 27; ++i) v.push_back(760'000'000 + ((i * 5'003'011) % 89) * 2'000'000);
  v.push_back(812'000'000);
  v.push_back(812'000'000);
  return v;
}
const std::vector<std::int64_t> kC{700'000'000, 700'000'000, 700'000'000, 800'000'000};

void expect_rel(double got, double want, double rel = 1e-9) {
  EXPECT_NEAR(got, want, std::fabs(want) * rel) << "want " << want;
}

TEST(Distributions, MatchScipy) {
  expect_rel(normal_cdf(-1.5), 0.06680720126885807);
  expect_rel(normal_sf(6.0), 9.865876450376946e-10);
  expect_rel(normal_quantile(0.975), 1.959963984540054);
  expect_rel(students_t_sf(2.1, 7), 0.0369355981064613);
  expect_rel(fisher_f_sf(3.2, 2, 40), 0.05138545607162816);
  expect_rel(beta_cdf(0.3, 2.5, 4), 0.3521975859067672);
  EXPECT_THROW(fisher_f_sf(1.0, -1.0, 3.0), core::Error);
}

TEST(MannWhitney, MatchesScipyWithTies) {
  const auto a = sample_a(), b = sample_b();
  const auto ab = mann_whitney(a, b);
  EXPECT_EQ(ab.u_a, 797.5);
  expect_rel(ab.p, 6.98945476985584e-06);
  const auto ba = mann_whitney(b, a);
  EXPECT_EQ(ba.u_a, 159.5);
  expect_rel(ba.p, 6.98945476985584e-06);
  EXPECT_NEAR(ab.probability_a_greater + ba.probability_a_greater, 1.0, 1e-15);
  const auto cb = mann_whitney(kC, b);
  EXPECT_EQ(cb.u_a, 7.0);
  expect_rel(cb.p, 0.005324263985147768);
}

TEST(MannWhitney, SmallSamplesWithoutTiesUseTheExactDistributionAsScipy) {
  // scipy.stats.mannwhitneyu(a, b) (SciPy 1.10, method "auto") on these samples: exact p where a
  // sample has at most 8 values and there are no ties, the asymptotic p otherwise.
  struct Case {
    std::vector<std::int64_t> a, b;
    double u_a, p;
    bool exact;
  };
  std::vector<std::int64_t> many;  // 3, 10, ..., 1396 and 1650
  for (std::int64_t i = 0; i < 200; ++i) many.push_back(i * 7 + 3);
  many.push_back(1650);
  const std::vector<Case> cases = {
      {{812, 905, 1003}, {700, 731, 760, 799, 845, 870, 880, 910, 933, 951}, 21.0, 0.3706293706293706, true},
      {{812, 905, 1003, 1100, 1201, 1250, 990, 870},
       {700, 731, 760, 799, 845, 880, 910, 933}, 55.0, 0.014763014763014764, true},
      {{1500, 1600, 1700, 1800, 1900}, many, 1003.0, 2.7175189225071713e-09, true},
      {{100, 101, 102}, {1, 2, 3, 4}, 12.0, 0.05714285714285714, true},
      {{1, 2, 3, 4, 5, 6, 7, 8, 9}, {10, 11, 12, 13, 14, 15, 16, 17, 18}, 0.0, 0.00041229480206169127, false},
  };
  for (const Case& c : cases) {
    const auto ab = mann_whitney(c.a, c.b);
    EXPECT_EQ(ab.u_a, c.u_a);
    EXPECT_EQ(ab.exact, c.exact);
    expect_rel(ab.p, c.p, 1e-12);
    const auto ba = mann_whitney(c.b, c.a);  // two-sided: the same p either way round
    EXPECT_EQ(ba.exact, c.exact);
    expect_rel(ba.p, c.p, 1e-12);
  }
  // A tie keeps the approximation (kC has three equal values), as in SciPy.
  EXPECT_FALSE(mann_whitney(kC, std::vector<std::int64_t>{1, 2, 3}).exact);
}

TEST(MannWhitney, UndefinedCasesGiveOne) {
  const std::vector<std::int64_t> same{5, 5, 5};
  EXPECT_EQ(mann_whitney(same, same).p, 1.0);
  EXPECT_EQ(mann_whitney({}, same).p, 1.0);
}

TEST(BrownForsythe, MatchesScipy) {
  const auto a = sample_a(), b = sample_b();
  const auto two = brown_forsythe(a, b);
  expect_rel(two.w, 10.122203201554562);
  expect_rel(two.p, 0.0023203812504784885, 1e-8);
  EXPECT_EQ(two.df1, 1.0);
  EXPECT_EQ(two.df2, 60.0);
  const std::span<const std::int64_t> groups[] = {a, b, kC};
  const auto three = brown_forsythe(std::span<const std::span<const std::int64_t>>(groups));
  expect_rel(three.w, 6.320310846326634);
  expect_rel(three.p, 0.0031509534209722906, 1e-8);
}

TEST(Newcombe, MatchesFormulaWithScipyQuantile) {
  const auto i = newcombe_interval(6, 63, 9, 66, 0.95);
  expect_rel(i.lower, -0.1559351594985506);
  expect_rel(i.upper, 0.07481794790739478);
  const auto j = newcombe_interval(0, 50, 3, 40, 0.90);
  expect_rel(j.lower, -0.17348017873690036);
  expect_rel(j.upper, -0.006978603991775412);
}

TEST(Compare, PointEstimatesTestsAndIntervals) {
  const auto a = sample_a(), b = sample_b();
  CompareOptions o;
  o.thresholds = {900ms, 1s};
  o.uncertainty_ms = 150.0;
  const auto c = compare(a, b, o);
  EXPECT_EQ(c.n_subject, a.size());
  EXPECT_DOUBLE_EQ(c.median_difference_ms, c.median_subject_ms - c.median_baseline_ms);
  EXPECT_TRUE(c.median_difference_ci_ms.contains(c.median_difference_ms));
  EXPECT_TRUE(c.iqr_ratio_ci.contains(c.iqr_ratio));
  EXPECT_TRUE(c.sd_ratio_ci.contains(c.sd_ratio));
  EXPECT_DOUBLE_EQ(c.iqr_ratio, c.iqr_subject_ms / c.iqr_baseline_ms);
  EXPECT_EQ(c.mann_whitney.p, mann_whitney(a, b).p);
  EXPECT_EQ(c.brown_forsythe.p, brown_forsythe(a, b).p);
  EXPECT_TRUE(c.location_significant());
  ASSERT_EQ(c.shares.size(), 2u);
  EXPECT_EQ(c.shares[1].count_baseline, 0u);
  EXPECT_GT(c.shares[1].count_subject, 0u);
  EXPECT_DOUBLE_EQ(c.shares[1].difference, c.shares[1].share_subject);
  // The median difference is 108 ms (950 - 842): below a 150 ms uncertainty, above a 10 ms one.
  EXPECT_TRUE(c.median_difference_below_uncertainty);
  o.uncertainty_ms = 10.0;
  EXPECT_FALSE(compare(a, b, o).median_difference_below_uncertainty);
}

TEST(Compare, SeededAndOrderFree) {
  const auto a = sample_a(), b = sample_b();
  auto reversed = a;
  std::reverse(reversed.begin(), reversed.end());
  const auto c1 = compare(a, b), c2 = compare(reversed, b);
  EXPECT_EQ(c1.median_difference_ci_ms.lower, c2.median_difference_ci_ms.lower);
  EXPECT_EQ(c1.sd_ratio_ci.upper, c2.sd_ratio_ci.upper);
  CompareOptions other;
  other.seed = 2;
  EXPECT_NE(compare(a, b, other).iqr_ratio_ci.lower, c1.iqr_ratio_ci.lower);
}

TEST(Compare, SameSampleGivesIntervalsAroundNoDifference) {
  // Equal samples with equal sizes: derived seeds differ, so the intervals straddle 0 and 1.
  const auto a = sample_a();
  const auto c = compare(a, a);
  EXPECT_TRUE(c.median_difference_ci_ms.contains(0.0));
  EXPECT_TRUE(c.iqr_ratio_ci.contains(1.0));
  EXPECT_GT(c.median_difference_ci_ms.width(), 0.0);
  EXPECT_FALSE(c.location_significant());
  EXPECT_FALSE(c.spread_significant());
}

TEST(Compare, RefusesTinySamplesAndBadLevels) {
  const std::vector<std::int64_t> one{1};
  EXPECT_THROW(compare(one, sample_b()), core::Error);
  CompareOptions o;
  o.level = 1.5;
  EXPECT_THROW(compare(sample_a(), sample_b(), o), core::Error);
}

TEST(BootstrapSd, CentredOnTheSampleSd) {
  auto a = sample_a();
  std::sort(a.begin(), a.end());
  const auto sds = bootstrap_sd_ms(a, 500, 3);
  ASSERT_EQ(sds.size(), 500u);
  const auto i = percentile_interval(sds, 0.95);
  const auto c = compare(a, sample_b());
  EXPECT_TRUE(i.contains(c.sd_subject_ms));
}

}  // namespace
}  // namespace m2mlat::stats
