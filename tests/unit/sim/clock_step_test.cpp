// The simulated clock step: the reading jumps by the step at its time and stays there, the run
// records it once as a step sample, and the events after it carry it in their stamps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iterator>

#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;
using namespace std::chrono_literals;
using core::Role;

namespace m2mlat::sim::clock_step_test {

constexpr std::int64_t kStart = 1'780'304'400'000'000'000;

TEST(ClockStep, APerfectClockJumpsAtTheStepAndStays) {
  ClockConfig stepped;
  stepped.step_at = 10s;
  stepped.step = -40ms;
  ClockPair clocks({}, stepped, sync_profile("perfect"), kStart, 1);
  EXPECT_EQ(clocks.error(Role::effect, kStart + 10'000'000'000 - 1).count(), 0);
  EXPECT_EQ(clocks.error(Role::effect, kStart + 10'000'000'000).count(), -40'000'000);
  EXPECT_EQ(clocks.error(Role::effect, kStart + 500'000'000'000).count(), -40'000'000);
  EXPECT_EQ(clocks.error(Role::cause, kStart + 500'000'000'000).count(), 0);
}

TEST(ClockStep, ADisciplinedClockKeepsTheStep) {
  // The daemon's reference moved with the clock: it does not slew the step away.
  ClockConfig stepped;
  stepped.step_at = 30s;
  stepped.step = 40ms;
  ClockPair clocks({}, stepped, sync_profile("co_referenced"), kStart, 7);
  const double before = clocks.at(Role::effect, kStart + 29'000'000'000).error_ns -
                        clocks.at(Role::cause, kStart + 29'000'000'000).error_ns;
  for (std::int64_t s : {31, 60, 300}) {
    const std::int64_t t = kStart + s * 1'000'000'000;
    const double after = clocks.at(Role::effect, t).error_ns - clocks.at(Role::cause, t).error_ns;
    EXPECT_NEAR(after - before, 40e6, 2e6) << "at " << s << " s";
  }
}

TEST(ClockStep, TheRunRecordsTheStepOnceInTimeOrder) {
  RigConfig config = preset("static_wifi");
  config.manoeuvres = 40;
  config.effect_clock.step_at = 20s;
  config.effect_clock.step = 40ms;
  const auto run = simulate(config);
  std::vector<ClockSample> steps;
  std::copy_if(run.clock_samples.begin(), run.clock_samples.end(), std::back_inserter(steps),
               [](const ClockSample& s) { return s.step.count() != 0; });
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].node, Role::effect);
  EXPECT_EQ(steps[0].step, 40ms);
  EXPECT_EQ(steps[0].true_time.ns(), config.start.ns() + 20'000'000'000);
  EXPECT_TRUE(std::is_sorted(run.clock_samples.begin(), run.clock_samples.end(),
                             [](const auto& a, const auto& b) { return a.true_time.ns() < b.true_time.ns(); }));
  // Events after the step carry it: measured - true latency jumps by the step.
  std::int64_t before = 0, after = 0;
  for (const auto& p : run.pairs) {
    const auto error = (p.measured_latency - p.true_latency).count();
    const auto effect_true = run.effect_truth.at(static_cast<std::size_t>(p.effect_index)).true_time.ns();
    if (effect_true < steps[0].true_time.ns()) {
      ++before;
      EXPECT_LT(std::llabs(error), 5'000'000);
    } else {
      ++after;
      EXPECT_NEAR(static_cast<double>(error), 40e6, 5e6);
    }
  }
  EXPECT_GT(before, 5);
  EXPECT_GT(after, 5);
  // The vehicle's first edge after the step carries the flag; no other edge does.
  const auto flagged = std::count_if(run.effect_events.begin(), run.effect_events.end(),
                                     [](const auto& e) { return (e.flags & core::kFlagAfterClockStep) != 0; });
  EXPECT_EQ(flagged, 1);
  EXPECT_TRUE(std::none_of(run.cause_events.begin(), run.cause_events.end(),
                           [](const auto& e) { return (e.flags & core::kFlagAfterClockStep) != 0; }));
}

}  // namespace m2mlat::sim::clock_step_test
