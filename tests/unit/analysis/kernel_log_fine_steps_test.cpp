// Steps inside one level of a kernel log, found by the local-level model's GLR.
#include "m2mlat/analysis/kernel_log_fine_steps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

#include "m2mlat/analysis/kernel_log_steps.hpp"

namespace m2mlat::analysis::kernel_log_fine_steps_test {

constexpr std::int64_t kMs = 1'000'000;

struct Level {
  std::vector<std::int64_t> mono_ns, d_ns;
};

// `lines` lines `apart_ms` apart; d = a random walk of `wander_us` per sqrt(s) (the daemon's
// corrections), minus a printk delay uniform in 20..200 us, plus `drift_ppm` of the crystal, plus
// `step_ns` from line `step_line` on, plus a slew of `ramp_ppm` over lines [ramp_from, ramp_to).
struct Shape {
  int lines = 200;
  std::int64_t apart_ms = 2'500;
  double wander_us = 0;
  double drift_ppm = 0;
  std::int64_t step_ns = 0;
  int step_line = -1;
  double ramp_ppm = 0;
  int ramp_from = 0, ramp_to = 0;
};
Level make_level(const Shape& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<std::int64_t> delay(20'000, 200'000);
  Level out;
  double walk_ns = 0, ramp_ns = 0;
  for (int i = 0; i < s.lines; ++i) {
    const std::int64_t mono = 1'000 * 1'000 * kMs + i * s.apart_ms * kMs;
    const double tau = static_cast<double>(s.apart_ms) * 1e-3;
    if (i > 0) walk_ns += normal(rng) * s.wander_us * 1e3 * std::sqrt(tau);
    if (i > s.ramp_from && i <= s.ramp_to) ramp_ns += s.ramp_ppm * 1e-6 * static_cast<double>(s.apart_ms) * 1e6;
    const double drift = s.drift_ppm * 1e-6 * static_cast<double>(i * s.apart_ms) * 1e6;
    out.mono_ns.push_back(mono);
    out.d_ns.push_back(std::llround(walk_ns + ramp_ns + drift) - delay(rng) + (i >= s.step_line && s.step_line >= 0 ? s.step_ns : 0));
  }
  return out;
}

TEST(KernelLogFineSteps, AOneMillisecondStepOnAQuietClockIsFoundAtItsLineWithItsSize) {
  for (const std::int64_t step : {kMs, -kMs}) {
    Shape shape;
    shape.step_ns = step;
    shape.step_line = 83;
    shape.drift_ppm = 12;  // the crystal's: taken out as the level's median rate
    const auto level = make_level(shape, 1);
    const auto found = fine_steps(level.mono_ns, level.d_ns);
    ASSERT_EQ(found.steps.size(), 1u) << step;
    EXPECT_EQ(found.steps[0].line, 83u);
    EXPECT_LE(std::llabs(found.steps[0].size_ns - step), 4 * found.steps[0].sd_ns);
    EXPECT_LT(found.steps[0].sd_ns, 100'000);
    EXPECT_LT(found.floor_ns, 500'000);  // a printk delay of 20..200 us hides no step of 0.5 ms
  }
}

TEST(KernelLogFineSteps, AWanderingClockShowsNoStepItDidNotMakeAndStatesItsFloor) {
  Shape shape;
  shape.wander_us = 100;  // 160 us a line 2.5 s apart, as the simulator's 5G-synchronised boards
  int found_steps = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const auto level = make_level(shape, seed);
    const auto found = fine_steps(level.mono_ns, level.d_ns);
    found_steps += static_cast<int>(found.steps.size());
    EXPECT_GT(found.floor_ns, 800'000) << seed;
    EXPECT_LT(found.floor_ns, 2 * kMs) << seed;
  }
  EXPECT_EQ(found_steps, 0);
}

TEST(KernelLogFineSteps, AStepAboveTheFloorOfAWanderingClockIsFound) {
  Shape shape;
  shape.wander_us = 100;
  shape.step_line = 120;
  int right = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    shape.step_ns = seed % 2 == 0 ? 2 * kMs : -2 * kMs;
    const auto level = make_level(shape, seed);
    const auto found = fine_steps(level.mono_ns, level.d_ns);
    right += found.steps.size() == 1 && found.steps[0].line == 120 &&
             std::llabs(found.steps[0].size_ns - shape.step_ns) <= 4 * found.steps[0].sd_ns;
  }
  EXPECT_GE(right, 36);  // 95 % from the floor on; 2 ms lies above it
}

TEST(KernelLogFineSteps, ADaemonSlewingAtTheBoundIsNoStep) {
  // A follower taking over the other board's 40 ms step: 500 ppm for 80 s.
  Shape shape;
  shape.ramp_ppm = 500;
  shape.ramp_from = 60;
  shape.ramp_to = 92;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const auto level = make_level(shape, seed);
    EXPECT_TRUE(fine_steps(level.mono_ns, level.d_ns).steps.empty()) << seed;
  }
}

TEST(KernelLogFineSteps, AShortLevelSaysNothing) {
  Shape shape;
  shape.lines = 20;
  shape.step_ns = 5 * kMs;
  shape.step_line = 10;
  const auto level = make_level(shape, 1);
  const auto found = fine_steps(level.mono_ns, level.d_ns);
  EXPECT_TRUE(found.steps.empty());
  EXPECT_EQ(found.floor_ns, 0);
}

TEST(KernelLogFineSteps, TheKernelLogsClockCorrectsAOneMillisecondStepTheLevelsCannotSee) {
  // 1 ms over 2.5 s is within the levels' slewing allowance: only the model inside the level sees it.
  Shape shape;
  shape.step_ns = kMs;
  shape.step_line = 70;
  const auto level = make_level(shape, 3);
  std::vector<std::int64_t> realtime_ns, log_time_us;
  for (std::size_t i = 0; i < level.d_ns.size(); ++i) {
    log_time_us.push_back(level.mono_ns[i] / 1000);
    realtime_ns.push_back(1'780'303'400'000'000'000 + log_time_us.back() * 1000 + level.d_ns[i]);
  }
  const auto clock = kernel_log_clock(realtime_ns, log_time_us);
  ASSERT_EQ(clock.steps.size(), 1u);
  EXPECT_EQ(clock.steps[0].at_ns, realtime_ns[70]);
  ASSERT_TRUE(clock.steps[0].size_ns);
  EXPECT_LE(std::llabs(*clock.steps[0].size_ns - kMs), clock.steps[0].size_max_ns);
  EXPECT_FALSE(clock.limits.any());  // a floor under 1 ms: nothing to say
}

}  // namespace m2mlat::analysis::kernel_log_fine_steps_test
