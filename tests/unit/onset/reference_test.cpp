// The reference rig's detector: the exact samples of its onset and end on steps, the lag a fixed
// threshold gives a slow ramp, re-arming, a trace that begins in a motion, and no motion in noise.
#include "m2mlat/onset/reference.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "trace_util.hpp"

namespace m2mlat::onset {
namespace {

using test::kMs;
using test::kPeriod;

// A step of `rate` deg/s from t_on to t_off.
std::function<double(std::int64_t)> step(std::int64_t t_on, std::int64_t t_off, double rate) {
  return [=](std::int64_t t) { return t >= t_on && t < t_off ? rate : 0.0; };
}

TEST(Reference, StepOnsetAndEndAtTheSamplesTheAverageCrosses) {
  // Noise-free: the average of a 100 deg/s step reaches 25 deg/s at its 6th sample
  // (1 - 0.95^6 = 0.265 > 0.25 > 1 - 0.95^5) and falls below 25 at the 28th after the step down
  // (0.95^28 = 0.238, 0.95^27 = 0.250...: the average was just under 100).
  const std::int64_t on = 1000 * kPeriod, off = 3000 * kPeriod;
  const auto d = detect_reference(test::make_trace(5000 * kPeriod, step(on, off, 100), 0.0));
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_EQ(d.motions[0].onset_ns, on + 5 * kPeriod);
  EXPECT_EQ(d.motions[0].end_ns, off + 27 * kPeriod);
  EXPECT_NEAR(d.motions[0].peak_deg_s, 100.2, 0.1);  // with the trace's bias
  EXPECT_TRUE(d.motions[0].ended);
  EXPECT_FALSE(d.began_in_motion);
  // Uncertainty: the spacing over sqrt(12) and the 60 us bound over sqrt(3).
  EXPECT_EQ(d.motions[0].onset_sd_ns,
            std::llround(std::sqrt(125'000.0 * 125'000 / 12 + 60'000.0 * 60'000 / 3)));
}

TEST(Reference, LagsASlowRampByTheTimeItTakesToReach25) {
  // 100 deg/s^2 from t0: with the trace's bias (0.2 deg/s on z, 0.8 across) the magnitude reaches
  // 25 deg/s 247.9 ms after t0, and the average lags a ramp by (1 - alpha) / alpha = 19 samples
  // (2.4 ms): 250.2 ms.
  const std::int64_t t0 = 500 * kMs;
  const auto d = detect_reference(test::make_trace(2000 * kMs, test::ramp(t0, 100, 60, 200 * kMs)));
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_NEAR(static_cast<double>(d.motions[0].onset_ns - t0), 250.2e6, 0.5e6);
}

TEST(Reference, NoiseAloneIsNoMotion) {
  EXPECT_TRUE(detect_reference(test::make_trace(
                                   10'000 * kMs, [](std::int64_t) { return 0.0; }, 0.5))
                  .motions.empty());
}

TEST(Reference, ReArmsOnlyAfter10000StillSamples) {
  // Two 50 deg/s steps 9,000 samples apart: the second comes before re-arming and is not a motion.
  // 11,000 apart: both are.
  for (const std::int64_t gap : {9'000, 11'000}) {
    const std::int64_t a = 1000 * kPeriod, len = 2000 * kPeriod, b = a + len + gap * kPeriod;
    const auto d = detect_reference(test::make_trace(b + 4000 * kPeriod, [&](std::int64_t t) {
      return step(a, a + len, 50)(t) + step(b, b + len, 50)(t);
    }));
    EXPECT_EQ(d.motions.size(), gap > 10'000 ? 2u : 1u) << "gap " << gap;
  }
}

TEST(Reference, ATraceBeginningInAMotionReportsOnlyTheLaterOnes) {
  const std::int64_t end_first = 500 * kPeriod, second = end_first + 12'000 * kPeriod;
  const auto d = detect_reference(test::make_trace(second + 3000 * kPeriod, [&](std::int64_t t) {
    return step(0, end_first, 80)(t) + step(second, second + 1000 * kPeriod, 80)(t);
  }));
  EXPECT_TRUE(d.began_in_motion);
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_GT(d.motions[0].onset_ns, second);
}

TEST(Reference, AMotionAtTheTraceEndIsOpen) {
  const auto d = detect_reference(test::make_trace(2000 * kPeriod, step(1000 * kPeriod, 5000 * kPeriod, 80)));
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_FALSE(d.motions[0].ended);
  EXPECT_EQ(d.motions[0].end_ns, 1999 * kPeriod);
}

TEST(Reference, EmptyAndShortTracesHaveNoMotion) {
  core::RateTrace empty;
  EXPECT_TRUE(detect_reference(empty).motions.empty());
  EXPECT_TRUE(detect_reference(test::make_trace(3 * kPeriod, step(0, kPeriod, 10))).motions.empty());
}

TEST(Reference, BadOptionsNameTheField) {
  ReferenceOptions o;
  o.alpha = 0;
  try {
    detect_reference(test::make_trace(10 * kPeriod, step(0, 0, 0)), o);
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("alpha"), std::string::npos);
  }
}

}  // namespace
}  // namespace m2mlat::onset
