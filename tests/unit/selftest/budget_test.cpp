// The error budget: term arithmetic, the steering rate from a multi-magnet wheel, E_sync from a
// synctest document, and the reference study's inputs giving its 10-15 ms.
#include "m2mlat/selftest/budget.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/rig_sync.hpp"
#include "m2mlat/selftest/synctest.hpp"

namespace m2mlat::selftest {
namespace {

using namespace std::chrono_literals;

TEST(Budget, WorstCaseSumAndUncertaintyRootSumSquare) {
  // Worst cases add; the terms' standard uncertainties add in squares, U95 = 2 u.
  const auto b = make_budget({{"sync", 3'000, "given", 3'000}, {"kernel", 4'000, "given", 4'000}, {"circuit", 0, "given", 0}});
  EXPECT_EQ(b.total_ns, 7'000);
  EXPECT_DOUBLE_EQ(b.u_ns, 5'000);
  EXPECT_DOUBLE_EQ(b.expanded_ns(), 10'000);
  EXPECT_THROW(make_budget({{"sync", -1, "given", 0}}), core::Error);
  const auto j = budget_json(b);
  EXPECT_EQ(j["format"], "m2mlat-budget/2");
  EXPECT_EQ(j["terms"].size(), 3u);
  EXPECT_EQ(j["total_ns"], 7'000);
  EXPECT_DOUBLE_EQ(j["U95_ns"].get<double>(), 10'000);
  // A bound is uniform within it: u = bound / sqrt(3).
  EXPECT_NEAR(bound_term("circuit", 2'000, "").u_ns, 1'154.7, 0.1);
}

TEST(Budget, KernelAndCalibrationTerms) {
  EXPECT_EQ(kernel_term(5us, 12us, "").value_ns, 12'000);
  EXPECT_NEAR(kernel_term(5us, 12us, "").u_ns, 3'753, 1);  // sqrt((5^2 + 12^2) / 12) us: delays uniform in [0, L]
  EXPECT_NEAR(calibration_term(1.0, 100.0, "").u_ns, 10e6 / std::sqrt(3.0), 1);
  EXPECT_EQ(calibration_term(1.0, 100.0, "").value_ns, 10'000'000);  // 1 deg at 100 deg/s = 10 ms
  EXPECT_EQ(calibration_term(0.5, 250.0, "").value_ns, 2'000'000);
  EXPECT_THROW(calibration_term(1.0, 0.0, ""), core::Error);
  EXPECT_THROW(calibration_term(-1.0, 10.0, ""), core::Error);
  EXPECT_THROW(kernel_term(-1us, 1us, ""), core::Error);
}

TEST(Budget, SteeringRateFromMagnets) {
  // Four magnets 30 deg apart; manoeuvres at 150, 300 and 200 deg/s, seconds apart.
  std::vector<std::int64_t> edges;
  std::int64_t t = 1'000'000'000'000;
  for (double rate : {150.0, 300.0, 200.0}) {
    for (int k = 0; k < 4; ++k) edges.push_back(t + std::llround(k * 30.0 / rate * 1e9));
    t += 3'000'000'000;
  }
  const auto r = steering_rate(edges, 30.0, 250ms, 1ms);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->intervals, 9u);
  EXPECT_NEAR(r->median_deg_s, 200.0, 1e-6);
  EXPECT_NEAR(r->p5_deg_s, 150.0, 1e-6);
  EXPECT_FALSE(steering_rate(std::vector<std::int64_t>{0, 5'000'000'000}, 30.0, 250ms, 1ms));
  EXPECT_THROW(steering_rate(edges, 0.0, 250ms, 1ms), core::Error);
}

TEST(Budget, SyncTermFromASynctestDocument) {
  std::vector<OffsetSample> series;
  for (int i = 0; i < 20; ++i)
    series.push_back({i * 500'000'000LL, (i % 2 ? 1 : -1) * (100'000 + i * 1'000), {}, {}});
  const auto doc = synctest_json(analyse_offsets(series), false);
  const auto mean = sync_term_from_synctest(doc, "mean_abs", "t.json");
  EXPECT_EQ(mean.value_ns, 109'500);
  // u: the offsets' RMS, sqrt(mean^2 + sd^2), about the mean |offset| for offsets of either sign.
  EXPECT_GT(mean.u_ns, 100'000);
  EXPECT_LT(mean.u_ns, 120'000);
  EXPECT_EQ(sync_term_from_synctest(doc, "max_abs", "t.json").value_ns, 119'000);
  EXPECT_GT(sync_term_from_synctest(doc, "p95_abs", "t.json").value_ns, 117'000);
  EXPECT_THROW(sync_term_from_synctest(doc, "median", "t.json"), core::Error);
  EXPECT_THROW(sync_term_from_synctest(nlohmann::json{{"format", "x"}}, "mean_abs", "t.json"), core::Error);
}

// The reference study's inputs: ~0.3 ms mean sync offset (its one-hour co-referenced test when
// present, else that figure), ~5 us cyclictest, 1 deg misalignment at 100 deg/s. It quoted 10-15 ms.
TEST(Budget, ReferenceStudyInputsGiveItsTenToFifteenMilliseconds) {
  BudgetTerm sync{"sync", 300'000, "the study's figure"};
  const auto path = std::filesystem::path(M2MLAT_TEST_DATA) / ".." / ".." / ".." / "shared" / "data" /
                    "upstream-results" / "Co_Referenced.csv";
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    const auto doc =
        synctest_json(synctest_from_rig(formats::import_rig_sync_csv(text.str(), path.string())), false);
    sync = sync_term_from_synctest(doc, "mean_abs", path.string());
  }
  const auto b = make_budget({sync,
                              kernel_term(5us, 5us, "cyclictest"),
                              {"circuit", kA3144SwitchingNs, "A3144"},
                              calibration_term(1.0, 100.0, "")});
  EXPECT_GE(b.total_ns, 10'000'000);
  EXPECT_LE(b.total_ns, 15'000'000);
  EXPECT_NEAR(static_cast<double>(b.total_ns) / 1e6, 10.3, 0.06);
}

}  // namespace
}  // namespace m2mlat::selftest
