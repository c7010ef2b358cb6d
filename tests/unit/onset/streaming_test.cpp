// The streaming (causal) onset detector: one detection per motion, none at rest, re-armed after a
// quiet time, and its delay after the true onset measured on the gyroscope twin (sim/gyro with
// sim/gyro_motion's hand and actuator motions) per speed class: the figures docs/onset.md states.
#include "m2mlat/onset/streaming.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/gyro.hpp"
#include "m2mlat/sim/gyro_motion.hpp"
#include "m2mlat/sim/random.hpp"
#include "trace_util.hpp"

namespace m2mlat::onset {
namespace {

using test::kMs;

// The stamps of the samples at which the detector fired.
std::vector<std::int64_t> streaming_onsets(const core::RateTrace& trace, StreamingOptions o = {}) {
  StreamingDetector d(trace.counts_per_deg_s, o);
  std::vector<std::int64_t> out;
  for (const auto& s : trace.samples)
    if (d.add(s)) out.push_back(s.time_ns);
  return out;
}

TEST(StreamingDetector, FiresOncePerMotionAndNeverAtRest) {
  const std::int64_t s = 1'000'000'000;
  const std::vector<sim::RateMotion> motions{sim::hand_motion(1 * s, 40, s / 2, 1),
                                             sim::hand_motion(3 * s, 200, s / 3, -1),
                                             sim::hand_motion(5 * s, 25, s, 1)};
  const auto trace = sim::simulate_gyro(sim::GyroConfig{}, motions, 0, 7 * s, 3, 0);
  const auto found = streaming_onsets(trace);
  ASSERT_EQ(found.size(), motions.size());
  for (std::size_t i = 0; i < motions.size(); ++i) {
    EXPECT_GE(found[i], motions[i].onset_ns);  // causal: never before the motion began
    EXPECT_LT(found[i], motions[i].onset_ns + 60 * kMs);  // the slow one (25 deg/s peak) is the latest
  }
  // 20 s of rest, noise and bias walk included: nothing.
  const auto still = sim::simulate_gyro(sim::GyroConfig{}, {}, 0, 20 * s, 4, 0);
  EXPECT_TRUE(streaming_onsets(still).empty());
}

TEST(StreamingDetector, LearnsOnlyAtRestAndReArmsAfterTheQuietTime) {
  // Starts in a motion: no onset until rest was learned; then a motion 50 ms after the last one's
  // end is not a new onset (quiet_ns 100 ms), one 300 ms after is.
  const auto rate = [](std::int64_t t) {
    if (t < 200 * kMs) return 30.0;
    if (t >= 600 * kMs && t < 700 * kMs) return 30.0;
    if (t >= 750 * kMs && t < 800 * kMs) return 30.0;
    if (t >= 1100 * kMs && t < 1200 * kMs) return 30.0;
    return 0.0;
  };
  const auto trace = test::make_trace(1500 * kMs, rate);
  StreamingDetector d(131, {});
  std::vector<std::int64_t> found;
  for (const auto& x : trace.samples) {
    if (x.time_ns < 200 * kMs) {
      EXPECT_FALSE(d.add(x));
      continue;
    }
    if (d.add(x)) found.push_back(x.time_ns);
  }
  ASSERT_EQ(found.size(), 2u);
  EXPECT_NEAR(static_cast<double>(found[0]), 600.0 * kMs, 1.0 * kMs);
  EXPECT_NEAR(static_cast<double>(found[1]), 1100.0 * kMs, 1.0 * kMs);
  EXPECT_GT(d.threshold_deg_s(), 0.1);
  EXPECT_LT(d.threshold_deg_s(), 2.0);
}

TEST(StreamingDetector, RefusesOptionsOutOfRange) {
  EXPECT_THROW(StreamingDetector(0, {}), core::Error);
  StreamingOptions o;
  o.k = 0;
  EXPECT_THROW(StreamingDetector(131, o), core::Error);
  o = {};
  o.quiet_ns = 0;
  EXPECT_THROW(StreamingDetector(131, o), core::Error);
  o = {};
  o.smooth_alpha = 1.5;
  EXPECT_THROW(StreamingDetector(131, o), core::Error);
}

// The delay after the true onset per speed class (the hand's peak rate; the actuator answers it
// within its limits), 60 motions each, on traces like `m2mlat onsettest`'s: 0.3..0.6 s of rest, the
// motion, 0.3 s of rest. Printed for docs/onset.md; the bounds asserted are the documented ones.
TEST(StreamingDetector, DelayAfterTheTrueOnsetPerSpeedClass) {
  struct Class {
    const char* name;
    double lo, hi;              // peak rate, deg/s
    double median_ms, p95_ms;   // documented bounds
  };
  const Class classes[] = {{"slow", 20, 50, 28, 45}, {"medium", 50, 150, 17, 29}, {"fast", 150, 400, 12, 19}};
  sim::Rng plan(7, 99);
  for (const auto& c : classes) {
    for (const char* profile : {"hand", "actuator"}) {
      std::vector<double> delays;
      int missed = 0, extra = 0;
      for (int i = 0; i < 60; ++i) {
        const std::int64_t rest = 300 * kMs + plan.uniform_int(0, 300 * kMs);
        const auto hand = sim::hand_motion(rest, plan.uniform(c.lo, c.hi),
                                           400 * kMs + plan.uniform_int(0, 800 * kMs), i % 2 ? 1 : -1);
        const auto m = profile[0] == 'h' ? hand : sim::actuator_motion(hand, 0, sim::ActuatorLimits{});
        const std::vector<sim::RateMotion> ms{m};
        const auto trace = sim::simulate_gyro(sim::GyroConfig{}, ms, 0, m.end_ns() + 300 * kMs, 11,
                                              static_cast<std::uint64_t>(i));
        const auto found = streaming_onsets(trace);
        if (found.empty()) {
          ++missed;
          continue;
        }
        extra += static_cast<int>(found.size()) - 1;
        delays.push_back(static_cast<double>(found.front() - m.onset_ns) / 1e6);
      }
      ASSERT_FALSE(delays.empty()) << profile << " " << c.name;
      std::sort(delays.begin(), delays.end());
      const auto at = [&](double q) { return delays[static_cast<std::size_t>(q * static_cast<double>(delays.size() - 1) + 0.5)]; };
      std::printf("streaming %-8s %-6s n=%zu median %.3f ms p95 %.3f ms min %.3f ms max %.3f ms\n", profile,
                  c.name, delays.size(), at(0.5), at(0.95), delays.front(), delays.back());
      EXPECT_EQ(missed, 0) << profile << " " << c.name;
      EXPECT_EQ(extra, 0) << profile << " " << c.name;
      EXPECT_GE(delays.front(), 0) << "an onset before the motion: " << profile << " " << c.name;
      EXPECT_LE(at(0.5), c.median_ms) << profile << " " << c.name;
      EXPECT_LE(at(0.95), c.p95_ms) << profile << " " << c.name;
    }
  }
}

}  // namespace
}  // namespace m2mlat::onset
