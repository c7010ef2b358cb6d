// The clocks: errors by synchronisation mode, the daemon's error bound, and free-running drift.
#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "sim_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;
using namespace std::chrono_literals;
using core::Role;

namespace {
// Vehicle clock error - operator clock error at each sample time (what a shared pulse measures), ms.
std::vector<double> disagreement_ms(const Simulation& run) {
  std::vector<double> out;
  for (std::size_t i = 0; i + 1 < run.clock_samples.size(); i += 2) {
    const auto& c = run.clock_samples[i];
    const auto& e = run.clock_samples[i + 1];
    EXPECT_EQ(c.node, Role::cause);
    EXPECT_EQ(e.node, Role::effect);
    EXPECT_EQ(c.true_time, e.true_time);
    out.push_back(static_cast<double>((e.error - c.error).count()) / 1e6);
  }
  return out;
}

Simulation run_sync(std::string_view preset_name, std::string_view sync, std::int64_t manoeuvres = 2000,
                    double max_slew_ppm = 500) {
  RigConfig config = preset(preset_name);
  config.sync = sync_profile(sync);
  config.sync.max_slew_ppm = max_slew_ppm;
  config.manoeuvres = manoeuvres;
  config.clock_sample_interval = 1s;
  return simulate(config);
}

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}
}  // namespace

TEST(Clocks, CoReferencedAgreeMoreTightlyThanAutonomous) {
  const auto co = disagreement_ms(run_sync("dynamic_co_referenced", "co_referenced"));
  const auto au = disagreement_ms(run_sync("dynamic_autonomous", "autonomous"));
  ASSERT_GT(co.size(), 3000u);
  // The study's sync test: co-referenced mean 0.21 ms (std 0.53, spikes to 4.4 ms); autonomous mean
  // -0.24 ms (std 0.31). Co-referenced is tighter in its core, but has the rarer large spikes.
  EXPECT_LT(test::iqr(co), test::iqr(au));
  EXPECT_NEAR(mean(co), 0.21, 0.1);
  EXPECT_NEAR(mean(au), -0.24, 0.1);
  EXPECT_LT(test::iqr(co), 0.5);
  EXPECT_LT(test::iqr(au), 0.8);
  // The spikes: a delayed sync packet pulls the vehicle's clock ahead. The study's rig (chrony's
  // default maxslewrate, 83333 ppm) saw them reach 4.4 ms; slewed at most 500 ppm (m2mlat's chrony.conf
  // and the simulator's default) the clock moves 0.5 ms a poll and the next poll pulls it back.
  EXPECT_LT(test::quantile(co, 1.0), 2.0);
  EXPECT_GT(test::quantile(disagreement_ms(run_sync("dynamic_co_referenced", "co_referenced", 2000, 83333)), 1.0), 2.0);
  EXPECT_LT(std::abs(test::quantile(au, 0.0)), 3.0);
}

TEST(Clocks, MeasuredLatencyDiffersByTheClocksDisagreement) {
  const Simulation run = run_sync("static_5g", "autonomous", 500);
  double largest_gap_us = 0;
  for (const TruePair& pair : run.pairs) {
    const auto gap = pair.measured_latency - pair.true_latency;
    largest_gap_us = std::max(largest_gap_us, std::abs(static_cast<double>(gap.count()) / 1e3));
  }
  EXPECT_GT(largest_gap_us, 50);    // the clocks do disagree ...
  EXPECT_LT(largest_gap_us, 5000);  // ... by far less than the latency
}

TEST(Clocks, PerfectClocksReadTrueTime) {
  const Simulation run = run_sync("static_wifi", "perfect", 200);
  for (const auto& s : run.clock_samples) {
    EXPECT_EQ(s.error, 0ns);
    EXPECT_EQ(s.error_bound, 0ns);
  }
  for (const TruePair& pair : run.pairs) {
    const auto& c = run.cause_truth[static_cast<std::size_t>(pair.cause_index)];
    const auto& e = run.effect_truth[static_cast<std::size_t>(pair.effect_index)];
    EXPECT_EQ(pair.measured_latency - pair.true_latency, e.irq_latency - c.irq_latency);
  }
}

TEST(Clocks, FreeClocksDriftFromTheirOffsets) {
  ClockConfig cause{3ms, 10.0, 0.0, 0ns};
  ClockConfig effect{-2ms, -4.0, 0.0, 0ns};
  SyncConfig sync = sync_profile("free");
  const std::int64_t start = 1'780'304'400'000'000'000;
  ClockPair clocks(cause, effect, sync, start, 1);
  for (std::int64_t seconds : {0, 1, 10, 100, 3600}) {
    const std::int64_t t = start + seconds * 1'000'000'000 + 123'456'789;
    const double elapsed_s = static_cast<double>(t - start) / 1e9;
    EXPECT_NEAR(static_cast<double>(clocks.error(Role::cause, t).count()), 3e6 + 10e3 * elapsed_s, 2);
    EXPECT_NEAR(static_cast<double>(clocks.error(Role::effect, t).count()), -2e6 - 4e3 * elapsed_s, 2);
    EXPECT_EQ(clocks.at(Role::cause, t).error_bound, core::Duration::max());
  }
}

TEST(Clocks, WanderMovesAFreeClock) {
  ClockConfig wandering{0ns, 0.0, 0.01, 0ns};
  SyncConfig sync = sync_profile("free");
  const std::int64_t start = 0;
  ClockPair clocks(wandering, wandering, sync, start, 7);
  const std::int64_t day = 86'400'000'000'000;
  const auto a = clocks.error(Role::cause, day);
  const auto b = clocks.error(Role::effect, day);
  // A random walk of 0.01 ppm/sqrt(s) over a day: frequency ~3 ppm, offset tens of ms; independent.
  EXPECT_GT(std::abs(static_cast<double>(a.count())), 1e5);
  EXPECT_NE(a, b);
}

TEST(Clocks, SynchronisedClocksConvergeAndStayWithinTheirBound) {
  for (std::string_view mode : {"co_referenced", "autonomous"}) {
    RigConfig config = preset("static_wifi");
    config.sync = sync_profile(mode);
    config.cause_clock.drift_ppm = 40;  // a bad crystal: the daemon learns it
    config.effect_clock.drift_ppm = -60;
    config.manoeuvres = 1000;
    config.clock_sample_interval = 1s;
    const Simulation run = simulate(config);
    std::size_t outside = 0;
    double largest_ms = 0;
    for (const auto& s : run.clock_samples) {
      outside += std::abs(s.error.count()) > s.error_bound.count() ? 1 : 0;
      largest_ms = std::max(largest_ms, std::abs(static_cast<double>(s.error.count())) / 1e6);
    }
    EXPECT_EQ(outside, 0u) << mode;
    EXPECT_LT(largest_ms, 10) << mode;
  }
}

TEST(Clocks, QueriesMayNotGoBackBeforeTheModelsStep) {
  ClockPair clocks(ClockConfig{}, ClockConfig{}, sync_profile("co_referenced"), 0, 1);
  (void)clocks.error(Role::cause, 5'500'000'000);
  EXPECT_NO_THROW((void)clocks.error(Role::effect, 5'000'000'000));  // within the current step
  EXPECT_THROW((void)clocks.error(Role::effect, 4'000'000'000), core::Error);
}
