// The onset test on a modest number of simulated motions: the targets for the flank detector
// where they are met (fast motions, the baseline's median), the reference detector's lag beside it,
// and determinism. docs/onset.md gives the full run's table and says which targets are not met.
#include "m2mlat/selftest/onsettest.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::selftest {
namespace {

const OnsetRow& row(const OnsetTestResult& r, std::string_view detector, std::string_view profile,
                    std::string_view speed) {
  for (const auto& x : r.rows)
    if (x.detector == detector && x.profile == profile && x.speed == speed) return x;
  throw std::runtime_error("no row");
}

const BaselineRow& baseline(const OnsetTestResult& r, std::string_view detector, std::string_view speed) {
  for (const auto& x : r.baseline)
    if (x.detector == detector && x.speed == speed) return x;
  throw std::runtime_error("no baseline row");
}

// One run (30 motions a class, about 2 s) serves every check: ctest runs each test in its own
// process, so a shared fixture would run it once a test.
TEST(OnsetTest, ThirtyMotionsPerClass) {
  OnsetTestOptions o;
  o.motions = 30;
  const auto result = run_onsettest(o);

  {  // FlankFindsEveryMotionAndNothingElse
    for (const auto& x : result.rows)
      if (x.detector == "flank") {
        EXPECT_EQ(x.found, x.motions) << x.profile << " " << x.speed;
        EXPECT_EQ(x.extra, 0u) << x.profile << " " << x.speed;
        // Its stated sd is about right: ~95% of the errors within two (87-100% on this run).
        EXPECT_GE(x.within_2sd_share, 0.8) << x.profile << " " << x.speed;
      }
  }

  {  // FlankMeetsTheTargetsOnFastMotions
    for (const auto* profile : {"hand", "actuator"}) {
      const auto& x = row(result, "flank", profile, "fast");
      EXPECT_LE(x.onset.abs_p95_ns, 0.5e6) << profile;
    }
    const auto& b = baseline(result, "flank", "fast");
    EXPECT_LE(std::fabs(b.m2m.median_ns), 0.2e6);
    EXPECT_GE(b.m2m.p5_ns, -0.5e6);
    EXPECT_LE(b.m2m.p95_ns, 0.5e6);
  }

  {  // FlankHasNoRateDependentLagAndTheBaselineMedianIsNearZero
    for (const auto* speed : {"slow", "medium", "fast"}) {
      EXPECT_LT(std::fabs(row(result, "flank", "hand", speed).onset.median_ns), 0.5e6) << speed;
      // The median of 30 slow pairs scatters by about 0.3 ms (their spread is +-2 ms): -0.39 ms here;
      // the full run of docs/onset.md (100 a class) gives -0.06 ms.
      const double limit = std::string_view(speed) == "slow" ? 0.6e6 : 0.2e6;
      EXPECT_LT(std::fabs(baseline(result, "flank", speed).m2m.median_ns), limit) << speed;
    }
  }

  {  // ReferenceLagsByTensOfMillisecondsMoreTheSlowerTheMotion
    const double slow = row(result, "reference", "hand", "slow").onset.median_ns;
    const double fast = row(result, "reference", "hand", "fast").onset.median_ns;
    EXPECT_GT(fast, 20e6);
    EXPECT_GT(slow, 2 * fast);
    // And it misses slow motions that never reach 25 deg/s.
    EXPECT_LT(row(result, "reference", "hand", "slow").found, 30u);
  }

  {  // JsonCarriesEveryRow
    const auto j = onsettest_json(result);
    EXPECT_EQ(j["format"], "m2mlat-onsettest/1");
    EXPECT_EQ(j["onset"].size(), 12u);  // 2 detectors x 2 profiles x 3 speeds
    EXPECT_EQ(j["baseline"].size(), 6u);
    EXPECT_NE(onsettest_text(result).find("baseline"), std::string::npos);
  }
}

// A hand that is no polynomial (a raised cosine): the flank detector's model (a quartic start) is then
// only an approximation, as it is on a real hand. It still finds every motion and on fast motions stays
// within 1 ms (0.47 and 0.68 ms |p95| on this run; the minimum-jerk hand's 0.3 ms owe something to its
// curve being a quartic: docs/onset.md). Its stated sd, which knows nothing of the model's error,
// covers less: 77-97 % of the errors within two sd on this run (79 % on fast hands in docs/onset.md).
TEST(OnsetTest, AHandTheFlankModelDoesNotContain) {
  OnsetTestOptions o;
  o.motions = 30;
  o.detectors = {"flank"};
  o.hand_shape = sim::RateMotion::Shape::raised_cosine;
  const auto result = run_onsettest(o);
  for (const auto& x : result.rows) {
    EXPECT_EQ(x.found, x.motions) << x.profile << " " << x.speed;
    EXPECT_EQ(x.extra, 0u) << x.profile << " " << x.speed;
    EXPECT_GE(x.within_2sd_share, 0.7) << x.profile << " " << x.speed;
    if (x.speed == "fast") {
      EXPECT_LE(x.onset.abs_p95_ns, 1.0e6) << x.profile;
      EXPECT_LT(std::fabs(x.onset.median_ns), 0.4e6) << x.profile;
    }
  }
  EXPECT_EQ(onsettest_json(result)["hand_shape"], "raised-cosine");
}

TEST(OnsetTestRun, DeterministicAndChecked) {
  OnsetTestOptions o;
  o.motions = 2;
  o.detectors = {"flank"};
  const auto a = run_onsettest(o), b = run_onsettest(o);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    EXPECT_EQ(a.rows[i].onset.median_ns, b.rows[i].onset.median_ns);
  o.detectors = {"nope"};
  EXPECT_THROW(run_onsettest(o), core::Error);
  o.detectors = {"flank"};
  o.motions = 0;
  EXPECT_THROW(run_onsettest(o), core::Error);
}

}  // namespace
}  // namespace m2mlat::selftest
