// The simulated gyroscope: its truth (rates, angles, the actuator's limits), its noise and scale,
// the reader's stamps and bounds (they hold the true sample instant), and determinism per seed.
#include "m2mlat/sim/gyro.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/gyro_motion.hpp"

namespace m2mlat::sim {
namespace {

constexpr std::int64_t kMs = 1'000'000;

// The angle turned by `m`, integrating its rate at 10 us steps, deg.
double angle(const RateMotion& m) {
  double sum = 0;
  for (std::int64_t t = m.onset_ns; t < m.end_ns(); t += 10'000) sum += rate_deg_s(m, t) * 1e-5;
  return sum;
}

TEST(GyroMotion, HandStartsAtRestPeaksMidwayAndTurnsItsAngle) {
  const auto m = hand_motion(100 * kMs, 200, 600 * kMs, -1);
  EXPECT_EQ(m.onset_ns, 100 * kMs);
  EXPECT_EQ(m.end_ns(), 700 * kMs);
  EXPECT_EQ(rate_deg_s(m, 100 * kMs - 1), 0);
  EXPECT_EQ(rate_deg_s(m, 100 * kMs), 0);                // zero rate at the onset
  EXPECT_LT(std::fabs(rate_deg_s(m, 101 * kMs)), 0.01);  // and zero acceleration: ~t^2
  EXPECT_NEAR(rate_deg_s(m, 400 * kMs), -200, 1e-9);     // the peak, mid-way
  EXPECT_NEAR(angle(m), m.amplitude_deg, 0.01);
  EXPECT_NEAR(m.amplitude_deg, -200 * 0.6 / 1.875, 1e-9);
  EXPECT_THROW(hand_motion(0, 0, kMs, 1), core::Error);
}

TEST(GyroMotion, RaisedCosineHandStartsAtRestPeaksMidwayAndTurnsItsAngle) {
  const auto m = hand_motion(100 * kMs, 200, 600 * kMs, 1, RateMotion::Shape::raised_cosine);
  EXPECT_EQ(m.shape, RateMotion::Shape::raised_cosine);
  EXPECT_EQ(rate_deg_s(m, 100 * kMs), 0);
  EXPECT_LT(std::fabs(rate_deg_s(m, 101 * kMs)), 0.01);  // ~t^2 at first, as a hand must
  EXPECT_NEAR(rate_deg_s(m, 400 * kMs), 200, 1e-9);
  EXPECT_NEAR(angle(m), m.amplitude_deg, 0.01);
  EXPECT_NEAR(m.amplitude_deg, 200 * 0.6 / 2, 1e-9);
  // Not a minimum-jerk curve: a quarter of the way in, at the same peak, it is at 0.5 of its peak, the
  // minimum-jerk curve at 30 (3/16)^2 / 1.875 = 0.5625.
  const auto j = hand_motion(100 * kMs, 200, 600 * kMs, 1);
  EXPECT_GT(std::fabs(rate_deg_s(m, 250 * kMs) - rate_deg_s(j, 250 * kMs)), 5);
  EXPECT_EQ(parse_hand_shape("raised-cosine"), RateMotion::Shape::raised_cosine);
  EXPECT_EQ(hand_shape_name(parse_hand_shape("minimum-jerk")), "minimum-jerk");
  EXPECT_THROW(parse_hand_shape("trapezoid"), core::Error);
  EXPECT_THROW(hand_motion(0, 100, kMs, 1, RateMotion::Shape::trapezoid), core::Error);
}

TEST(GyroMotion, ActuatorRepeatsWithinItsLimitsAndSaturatesBeyond) {
  const ActuatorLimits limits{360, 1500};
  // Slow: within the limits, the same rotation 80 ms later.
  const auto slow = hand_motion(0, 40, 800 * kMs, 1);
  const auto follow = actuator_motion(slow, 80 * kMs, limits);
  EXPECT_EQ(follow.shape, RateMotion::Shape::minimum_jerk);
  EXPECT_EQ(follow.onset_ns, 80 * kMs);
  EXPECT_DOUBLE_EQ(rate_deg_s(follow, 480 * kMs), rate_deg_s(slow, 400 * kMs));
  // Fast: 400 deg/s over 0.4 s is beyond both limits: a trapezoid at them, turning the same angle.
  const auto fast = hand_motion(0, 400, 400 * kMs, 1);
  const auto sat = actuator_motion(fast, 100 * kMs, limits);
  EXPECT_EQ(sat.shape, RateMotion::Shape::trapezoid);
  EXPECT_EQ(sat.onset_ns, 100 * kMs);
  EXPECT_LE(sat.peak_deg_s, 360);
  EXPECT_NEAR(rate_deg_s(sat, 110 * kMs), 1500 * 0.010, 1e-6);  // constant acceleration from rest
  EXPECT_NEAR(angle(sat), fast.amplitude_deg, 0.05);
  EXPECT_GT(sat.duration_ns, fast.duration_ns);
}

TEST(Gyro, StillChipHasItsNoiseAndBiasAndOneCountResolution) {
  GyroConfig config;
  const auto trace = simulate_gyro(config, {}, 0, 2000 * kMs, 1, 0);
  EXPECT_EQ(trace.clock, core::Clock::simulated);
  EXPECT_EQ(trace.counts_per_deg_s, 131);
  EXPECT_NEAR(static_cast<double>(trace.samples.size()), 16000, 50);  // 8 kHz for 2 s
  for (std::size_t a = 0; a < 3; ++a) {
    double sum = 0, sum2 = 0;
    for (const auto& s : trace.samples) sum += s.raw[a];
    const double mean = sum / static_cast<double>(trace.samples.size());
    for (const auto& s : trace.samples) sum2 += (s.raw[a] - mean) * (s.raw[a] - mean);
    const double sd = std::sqrt(sum2 / static_cast<double>(trace.samples.size())) / 131;
    EXPECT_NEAR(sd, config.noise_sd_deg_s(), 0.15 * config.noise_sd_deg_s()) << "axis " << a;
    EXPECT_LT(std::fabs(mean / 131), 5 * config.bias_sd_deg_s) << "axis " << a;
  }
  EXPECT_NEAR(config.noise_sd_deg_s(), 0.1, 0.001);  // the datasheet's density over 256 Hz
}

TEST(Gyro, ARotationReadsAsItsRateTimes131) {
  GyroConfig config;
  config.tilt_sd = 0;
  config.bias_sd_deg_s = 0;
  config.bias_walk_deg_s_rts = 0;
  RateMotion spin;  // a trapezoid held at 100 deg/s
  spin.shape = RateMotion::Shape::trapezoid;
  spin.duration_ns = 1000 * kMs;
  spin.amplitude_deg = 95;
  spin.accel_deg_s2 = 1e6;
  spin.peak_deg_s = 100;
  const auto trace = simulate_gyro(config, std::span(&spin, 1), 100 * kMs, 900 * kMs, 3, 0);
  double sum = 0;
  for (const auto& s : trace.samples) sum += s.raw[2];
  EXPECT_NEAR(sum / static_cast<double>(trace.samples.size()), 13100, 2);
}

TEST(Gyro, StampsIncreaseAndTheirBoundsHoldTheTrueInstant) {
  // A rate step (1e7 deg/s^2: full rate within 20 us) at a known instant: the first reading that
  // shows it was taken after the onset, the one before it before onset + 20 us; each stamp's bound
  // must allow that.
  GyroConfig config;
  RateMotion step;
  step.shape = RateMotion::Shape::trapezoid;
  step.accel_deg_s2 = 1e7;
  step.peak_deg_s = 200;
  step.amplitude_deg = 100;
  step.duration_ns = 500 * kMs + 20'000;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    step.onset_ns = 100 * kMs + static_cast<std::int64_t>(seed) * 7'777;
    const auto trace = simulate_gyro(config, std::span(&step, 1), 0, 300 * kMs, seed, 0);
    std::size_t first = 0;
    for (std::size_t i = 0; i < trace.samples.size(); ++i) {
      if (i > 0) {
        ASSERT_GT(trace.samples[i].time_ns, trace.samples[i - 1].time_ns);
      }
      ASSERT_GT(trace.samples[i].bound_ns, 0);
      if (!first && std::abs(trace.samples[i].raw[2]) > 131 * 50) first = i;
    }
    ASSERT_GT(first, 0u);
    const auto& on = trace.samples[first];
    const auto& before = trace.samples[first - 1];
    EXPECT_GE(on.time_ns + on.bound_ns, step.onset_ns) << seed;
    EXPECT_LE(before.time_ns - before.bound_ns, step.onset_ns + 20'000) << seed;
    // The bound is about half a period plus half a read: 60 to 150 us with the defaults.
    EXPECT_GT(on.bound_ns, 60'000);
    EXPECT_LT(on.bound_ns, 150'000);
  }
}

TEST(Gyro, DeterministicPerSeedAndChip) {
  GyroConfig config;
  const auto m = hand_motion(200 * kMs, 100, 500 * kMs, 1);
  const auto a = simulate_gyro(config, std::span(&m, 1), 0, 1000 * kMs, 5, 0);
  const auto b = simulate_gyro(config, std::span(&m, 1), 0, 1000 * kMs, 5, 0);
  const auto c = simulate_gyro(config, std::span(&m, 1), 0, 1000 * kMs, 5, 1);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    ASSERT_EQ(a.samples[i].time_ns, b.samples[i].time_ns);
    ASSERT_EQ(a.samples[i].raw, b.samples[i].raw);
  }
  EXPECT_NE(a.samples[100].raw, c.samples[100].raw);      // another chip: its own noise and bias
  EXPECT_NE(a.samples[0].time_ns, c.samples[0].time_ns);  // and its own sample phase
}

TEST(Gyro, BadConfigurationNamesTheField) {
  GyroConfig config;
  config.period_ns = 0;
  try {
    simulate_gyro(config, {}, 0, kMs, 1, 0);
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("period_ns"), std::string::npos);
  }
}

}  // namespace
}  // namespace m2mlat::sim
