// The full summary against numpy and Python's statistics module. Every expected number is
// printed by reference_values.py under the name in the comment.
#include "m2mlat/stats/summary.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "samples.hpp"

using namespace m2mlat::stats;
using namespace std::chrono_literals;
using m2mlat::stats::test::expect_close;

namespace {

// One sample's reference values (all ms, as Summary).
struct Reference {
  std::size_t min_index, max_index;
  std::int64_t min_ns, max_ns;
  double mean, sd;
  double p0, p5, p12_5, p25, p50, p75, p90, p95, p99, p99_9, p100, iqr;
  std::size_t above_170, above_300, above_400, above_1000;
};

void check(const std::vector<std::int64_t>& v, const Reference& r) {
  SummaryOptions options;
  options.extra_percentiles = {0, 12.5, 99.9, 100};
  const Summary s = summarize(v, {}, options);
  EXPECT_EQ(s.n, v.size());
  ASSERT_TRUE(s.min && s.max);
  EXPECT_EQ(s.min->ns, r.min_ns);
  EXPECT_EQ(s.min->index, r.min_index);
  EXPECT_EQ(s.min->id, static_cast<std::int64_t>(r.min_index));  // no ids: the index
  EXPECT_EQ(s.max->ns, r.max_ns);
  EXPECT_EQ(s.max->index, r.max_index);
  expect_close(s.mean_ms, r.mean);
  expect_close(s.sd_ms, r.sd);
  expect_close(s.p5_ms, r.p5);
  expect_close(s.q1_ms, r.p25);
  expect_close(s.median_ms, r.p50);
  expect_close(s.q3_ms, r.p75);
  expect_close(s.p90_ms, r.p90);
  expect_close(s.p95_ms, r.p95);
  expect_close(s.p99_ms, r.p99);
  expect_close(s.iqr_ms, r.iqr);
  ASSERT_EQ(s.extra_percentiles.size(), 4u);
  EXPECT_EQ(s.extra_percentiles[1].percent, 12.5);
  expect_close(s.extra_percentiles[0].value_ms, r.p0);
  expect_close(s.extra_percentiles[1].value_ms, r.p12_5);
  expect_close(s.extra_percentiles[2].value_ms, r.p99_9);
  expect_close(s.extra_percentiles[3].value_ms, r.p100);
  ASSERT_EQ(s.thresholds.size(), 4u);
  const std::size_t above[] = {r.above_170, r.above_300, r.above_400, r.above_1000};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(s.thresholds[i].count_above, above[i]) << i;
    EXPECT_DOUBLE_EQ(s.thresholds[i].fraction_above,
                     static_cast<double>(above[i]) / static_cast<double>(v.size()));
  }
  EXPECT_FALSE(s.bootstrap);  // not requested
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST(Summary, OneSample) {  // reference: one.*
  check({812'345'678},
        {0,          0,          812'345'678, 812'345'678, 812.345678, kNaN,       812.345678, 812.345678,
         812.345678, 812.345678, 812.345678,  812.345678,  812.345678, 812.345678, 812.345678, 812.345678,
         812.345678, 0.0,        1,           1,           1,          0});
}

TEST(Summary, TwoSamples) {  // reference: two.*
  check({250'000'001, 150'000'000}, {1,
                                     0,
                                     150'000'000,
                                     250'000'001,
                                     200.0000005,
                                     70.71067882576153,
                                     150.0,
                                     155.00000005,
                                     162.500000125,
                                     175.00000025,
                                     200.0000005,
                                     225.00000075,
                                     240.0000009,
                                     245.00000095,
                                     249.00000099000002,
                                     249.900000999,
                                     250.000001,
                                     50.0000005,
                                     1,
                                     0,
                                     0,
                                     0});
}

TEST(Summary, OddWithTies) {  // reference: odd_ties.*
  check({5'000'000, 3'000'000, 3'000'000, 9'000'000, 1'000'000, 7'000'000, 3'000'000}, {4,
                                                                                        3,
                                                                                        1'000'000,
                                                                                        9'000'000,
                                                                                        4.428571428571428,
                                                                                        2.7602622373694166,
                                                                                        1.0,
                                                                                        1.6,
                                                                                        2.5,
                                                                                        3.0,
                                                                                        3.0,
                                                                                        6.0,
                                                                                        7.800000000000001,
                                                                                        8.399999999999999,
                                                                                        8.879999999999999,
                                                                                        8.988000000000001,
                                                                                        9.0,
                                                                                        3.0,
                                                                                        0,
                                                                                        0,
                                                                                        0,
                                                                                        0});
}

TEST(Summary, EvenWithNegativesAndTiedMinimum) {  // reference: even_negative.*
  // The minimum -2 ms occurs at indices 0 and 7: the first is reported, as numpy.argmin does.
  check({-2'000'000, 500, -7, 1'000'000'000, 3, 3, 42, -2'000'000}, {0,
                                                                     3,
                                                                     -2'000'000,
                                                                     1'000'000'000,
                                                                     124.500067625,
                                                                     353.7565477013848,
                                                                     -2.0,
                                                                     -2.0,
                                                                     -2.0,
                                                                     -0.50000525,
                                                                     3e-06,
                                                                     0.0001565,
                                                                     300.0003499999998,
                                                                     650.0001749999996,
                                                                     930.0000349999998,
                                                                     993.0000035000004,
                                                                     1000.0,
                                                                     0.50016175,
                                                                     1,
                                                                     1,
                                                                     1,
                                                                     0});
}

TEST(Summary, AroundTheThresholds) {  // reference: thresholds.*
  check({170'000'000, 170'000'001, 299'999'999, 300'000'000, 300'000'001, 400'000'000, 999'999'999,
         1'000'000'000, 1'000'000'001, 12'000, 2'500'000'000},
        {9,
         10,
         12'000,
         2'500'000'000,
         649.0920000909091,
         714.3721250218135,
         0.012,
         85.006,
         170.00000025,
         235.0,
         300.000001,
         999.9999995,
         1000.000001,
         1750.0000005,
         2350.0000001000003,
         2485.000000010003,
         2500.0,
         764.9999995,
         9,
         6,
         4,
         2});
}

TEST(Summary, LargerLcgSample) {  // reference: lcg10007.*
  check(test::lcg_sample(10007, 42), {6660,
                                      5210,
                                      120'011'504,
                                      1'019'988'046,
                                      525.594852175677,
                                      261.4533680758682,
                                      120.011504,
                                      155.0234519,
                                      208.40730175,
                                      297.315949,
                                      485.333003,
                                      752.8284445,
                                      909.445378,
                                      962.8406841999999,
                                      1008.01253394,
                                      1019.0381024200001,
                                      1019.988046,
                                      455.5124955,
                                      9293,
                                      7466,
                                      6108,
                                      166});
}

TEST(Summary, ExtremesNameTheirSample) {
  const std::vector<std::int64_t> v = {300, 100, 500, 100, 500};
  const std::vector<std::int64_t> ids = {7001, 7002, 7003, 7004, 7005};
  const Summary s = summarize(v, ids);
  ASSERT_TRUE(s.min && s.max);
  EXPECT_EQ(s.min->id, 7002);  // first of the tied minima
  EXPECT_EQ(s.min->index, 1u);
  EXPECT_EQ(s.max->id, 7003);
  EXPECT_EQ(s.max->index, 2u);
  EXPECT_DOUBLE_EQ(s.max->ms(), 0.0005);
  const std::vector<std::int64_t> short_ids = {1, 2};
  EXPECT_THROW((void)summarize(v, short_ids), m2mlat::core::Error);
}

TEST(Summary, InPlaceGivesTheSameSummaryAndSortsTheSample) {
  SummaryOptions options;
  options.extra_percentiles = {12.5, 99.9};
  options.bootstrap = BootstrapOptions{200, 4, 0.95};
  const auto v = test::lcg_sample(1001, 9);
  std::vector<std::int64_t> ids(v.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = 5000 + static_cast<std::int64_t>(i);
  const Summary copied = summarize(v, ids, options);
  auto sample = v;
  const Summary in_place = summarize_in_place(sample, ids, options);
  EXPECT_TRUE(std::is_sorted(sample.begin(), sample.end()));
  ASSERT_TRUE(in_place.min && in_place.max && in_place.bootstrap);
  EXPECT_EQ(in_place.min, copied.min);  // found before the sort: ids and positions of the input
  EXPECT_EQ(in_place.max, copied.max);
  EXPECT_EQ(in_place.mean_ms, copied.mean_ms);
  EXPECT_EQ(in_place.sd_ms, copied.sd_ms);
  EXPECT_EQ(in_place.median_ms, copied.median_ms);
  EXPECT_EQ(in_place.p99_ms, copied.p99_ms);
  EXPECT_EQ(in_place.extra_percentiles.at(1).value_ms, copied.extra_percentiles.at(1).value_ms);
  EXPECT_EQ(in_place.thresholds.at(0).count_above, copied.thresholds.at(0).count_above);
  EXPECT_EQ(in_place.bootstrap->median_ms.lower, copied.bootstrap->median_ms.lower);
  EXPECT_EQ(in_place.bootstrap->iqr_ms.upper, copied.bootstrap->iqr_ms.upper);
}

TEST(Summary, EmptySampleIsAllUndefined) {
  SummaryOptions options;
  options.extra_percentiles = {99.9};
  options.bootstrap = BootstrapOptions{};
  const Summary s = summarize({}, {}, options);
  EXPECT_EQ(s.n, 0u);
  EXPECT_FALSE(s.min);
  EXPECT_FALSE(s.max);
  for (const double x : {s.mean_ms, s.sd_ms, s.p5_ms, s.q1_ms, s.median_ms, s.q3_ms, s.p90_ms, s.p95_ms,
                         s.p99_ms, s.iqr_ms, s.extra_percentiles.at(0).value_ms}) {
    EXPECT_TRUE(std::isnan(x));
  }
  ASSERT_EQ(s.thresholds.size(), 4u);
  EXPECT_EQ(s.thresholds[0].count_above, 0u);
  EXPECT_FALSE(s.bootstrap);
}

TEST(Summary, CustomThresholds) {
  SummaryOptions options;
  options.thresholds = {50ms};
  const Summary s = summarize(std::vector<std::int64_t>{40'000'000, 50'000'000, 60'000'000}, {}, options);
  ASSERT_EQ(s.thresholds.size(), 1u);
  EXPECT_EQ(s.thresholds[0].count_above, 1u);
}

TEST(Summary, BadOptionsAreUsageErrors) {
  const std::vector<std::int64_t> v = {1, 2, 3};
  SummaryOptions options;
  options.extra_percentiles = {100.5};
  try {
    (void)summarize(v, {}, options);
    ADD_FAILURE() << "percentile 100.5 accepted";
  } catch (const m2mlat::core::Error& e) {
    EXPECT_EQ(e.kind(), m2mlat::core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("100.5"), std::string::npos) << e.what();
  }
  options.extra_percentiles.clear();
  options.bootstrap = BootstrapOptions{100, 1, 1.0};
  EXPECT_THROW((void)summarize(v, {}, options), m2mlat::core::Error);
}

TEST(Summary, IncludesBootstrapWhenAsked) {
  SummaryOptions options;
  options.bootstrap = BootstrapOptions{500, 3, 0.9};
  const auto v = test::lcg_sample(301, 5);
  const Summary s = summarize(v, {}, options);
  ASSERT_TRUE(s.bootstrap);
  EXPECT_EQ(s.bootstrap->resamples, 500u);
  EXPECT_EQ(s.bootstrap->seed, 3u);
  EXPECT_EQ(s.bootstrap->level, 0.9);
  EXPECT_TRUE(s.bootstrap->median_ms.contains(s.median_ms));
  EXPECT_TRUE(s.bootstrap->iqr_ms.contains(s.iqr_ms));
  // The same as asking the bootstrap directly for the sorted sample.
  const auto direct = bootstrap_median_iqr(test::sorted_copy(v), *options.bootstrap);
  ASSERT_TRUE(direct);
  EXPECT_EQ(direct->median_ms.lower, s.bootstrap->median_ms.lower);
  EXPECT_EQ(direct->iqr_ms.upper, s.bootstrap->iqr_ms.upper);
}
