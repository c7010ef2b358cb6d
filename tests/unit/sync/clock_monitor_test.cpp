// The clock monitor with a scripted clock (its twin of the kernel) and scripted chronyc/pmc
// outputs: which samples each batch adds, and when.
#include "m2mlat/sync/clock_monitor.hpp"

#include <gtest/gtest.h>
#include <sys/timex.h>

#include <nlohmann/json.hpp>

#include "m2mlat/store/clock_step.hpp"

#include "fixtures.hpp"

namespace m2mlat::sync {
namespace {

using testing::fixture;
using testing::ScriptedRunner;

constexpr std::int64_t kEpoch = 1'795'269'000'000'000'000;
constexpr std::int64_t kMs = 1'000'000;

// A clock the test moves by hand.
class FakeClocks final : public ClockSource {
 public:
  std::int64_t raw_ns = 0;
  std::int64_t step_ns = 0;  // realtime - raw - kEpoch
  KernelClockState state;
  FakeClocks() {
    state.available = true;
    state.synchronised = true;
    state.state = TIME_OK;
    state.status = STA_PLL;
    state.max_error_ns = 1000;
    state.est_error_ns = 10;
    state.tick_us = 10000;
  }
  KernelClockState kernel_state() override { return state; }
  ClockPair clock_pair() override { return {kEpoch + raw_ns + step_ns, raw_ns, 100}; }
};

std::vector<std::string> sources(const std::vector<store::ClockSample>& samples) {
  std::vector<std::string> out;
  for (const auto& s : samples) out.push_back(s.source);
  return out;
}

TEST(ClockMonitor, AdjtimexOnFirstCallThenOnlyWhenDueOrChanged) {
  FakeClocks clocks;
  MonitorOptions o;
  o.kernel_interval = std::chrono::seconds(1);
  ClockMonitor m(o, clocks, nullptr);
  std::vector<store::ClockSample> out;
  m.on_batch(7, out);
  ASSERT_EQ(sources(out), std::vector<std::string>{"adjtimex"});
  EXPECT_EQ(out[0].session_id, 7);
  EXPECT_EQ(out[0].time.ns(), kEpoch);

  out.clear();
  for (int i = 1; i < 10; ++i) {  // 900 ms of batches: nothing due, nothing changed
    clocks.raw_ns = i * 100 * kMs;
    m.on_batch(7, out);
  }
  EXPECT_TRUE(out.empty());
  clocks.raw_ns = 1000 * kMs;  // due
  m.on_batch(7, out);
  EXPECT_EQ(sources(out), std::vector<std::string>{"adjtimex"});

  out.clear();
  clocks.raw_ns += kMs;
  clocks.state.status |= STA_UNSYNC;  // a change is recorded at once
  clocks.state.synchronised = false;
  m.on_batch(7, out);
  ASSERT_EQ(sources(out), std::vector<std::string>{"adjtimex"});
  EXPECT_FALSE(out[0].synchronised);
  out.clear();
  clocks.raw_ns += kMs;
  clocks.state.max_error_ns += 500;  // the growing error bound alone is no change
  m.on_batch(7, out);
  EXPECT_TRUE(out.empty());
}

// A monitor with default options that has seen its first batch (its first readings), output cleared:
// what the step tests start from.
struct MonitorAfterFirstBatch {
  FakeClocks clocks;
  ClockMonitor m{{}, clocks, nullptr};
  std::vector<store::ClockSample> out;
  MonitorAfterFirstBatch() {
    m.on_batch(1, out);
    out.clear();
  }
};

TEST(ClockMonitor, AStepIsRecordedAtOnce) {
  MonitorAfterFirstBatch started;
  auto& [clocks, m, out] = started;
  clocks.raw_ns = 50 * kMs;
  clocks.step_ns = -40 * kMs;
  m.on_batch(1, out);
  ASSERT_EQ(sources(out), std::vector<std::string>{"step"});
  EXPECT_EQ(out[0].session_id, 1);
  EXPECT_EQ(nlohmann::json::parse(out[0].detail_json)["step_ns"], -40 * kMs);
  EXPECT_EQ(m.steps_detected(), 1u);
}

TEST(ClockMonitor, AStepRecordCarriesItsSizeAndWindow) {
  MonitorAfterFirstBatch started;
  auto& [clocks, m, out] = started;
  clocks.raw_ns = 50 * kMs;
  clocks.step_ns = 40 * kMs;
  m.on_batch(1, out);
  ASSERT_EQ(sources(out), std::vector<std::string>{"step"});
  const auto step = store::clock_step_of(out[0]);
  ASSERT_TRUE(step);
  EXPECT_EQ(step->size_ns, 40 * kMs);
  EXPECT_EQ(step->at_ns, kEpoch + 90 * kMs);
  // Somewhere between the two readings (50 ms apart), less the size's own allowance.
  EXPECT_LE(step->earliest_ns, kEpoch + 40 * kMs);
  EXPECT_GT(step->earliest_ns, kEpoch + 39 * kMs);
  EXPECT_LT(step->size_max_ns, 1 * kMs);  // 500 ppm of 50 ms plus the 100 ns windows
  EXPECT_EQ(step->origin, "monitor");
}

TEST(ClockMonitor, AKernelResetWithoutAVisibleSizeIsAStepOfUnknownSize) {
  MonitorAfterFirstBatch started;
  auto& [clocks, m, out] = started;
  // settimeofday() to about the same time: no size against CLOCK_MONOTONIC_RAW, but ntp_clear().
  clocks.raw_ns = 20 * kMs;
  clocks.state.synchronised = false;
  clocks.state.status = STA_UNSYNC;
  clocks.state.max_error_ns = 16'000'000'000;
  m.on_batch(1, out);
  ASSERT_EQ(sources(out), (std::vector<std::string>{"step", "adjtimex"}));
  const auto step = store::clock_step_of(out[0]);
  ASSERT_TRUE(step);
  EXPECT_FALSE(step->size_ns);
  EXPECT_EQ(step->earliest_ns, kEpoch);
  EXPECT_EQ(step->at_ns, kEpoch + 20 * kMs);
  EXPECT_EQ(step->origin, "adjtimex");
  EXPECT_EQ(m.steps_detected(), 1u);
  // Staying unsynchronised is no further step.
  out.clear();
  clocks.raw_ns = 40 * kMs;
  m.on_batch(1, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(m.steps_detected(), 1u);
}

TEST(ClockMonitor, ChronyAndPtpAtTheirOwnIntervals) {
  FakeClocks clocks;
  ScriptedRunner runner;
  const std::string chrony =
      fixture("chronyc_tracking_synchronised.csv") + fixture("chronyc_sources_synchronised.csv");
  runner.results = {ScriptedRunner::exited(0, chrony)};
  MonitorOptions o;
  o.kernel_interval = std::chrono::hours(1);
  o.chrony_interval = std::chrono::seconds(16);
  ClockMonitor m(o, clocks, &runner);
  std::vector<store::ClockSample> out;
  m.on_batch(3, out);
  EXPECT_EQ(sources(out), (std::vector<std::string>{"adjtimex", "chrony"}));
  out.clear();
  clocks.raw_ns = 15'000 * kMs;
  m.on_batch(3, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(runner.calls.size(), 1u);
  clocks.raw_ns = 16'000 * kMs;
  m.on_batch(3, out);
  ASSERT_EQ(sources(out), std::vector<std::string>{"chrony"});
  EXPECT_EQ(out[0].offset_ns, 1284);
  EXPECT_EQ(out[0].session_id, 3);
  EXPECT_EQ(runner.calls.size(), 2u);
}

TEST(ClockMonitor, AFailingProgramAddsNoSampleAndKeepsItsMessage) {
  FakeClocks clocks;
  ScriptedRunner runner;
  runner.results = {ScriptedRunner::exited(1, "506 Cannot talk to daemon\n"),
                    ScriptedRunner::exited(0, fixture("chronyc_tracking_synchronised.csv"))};
  MonitorOptions o;
  o.chrony_interval = std::chrono::seconds(1);
  ClockMonitor m(o, clocks, &runner);
  std::vector<store::ClockSample> out;
  m.on_batch(1, out);
  EXPECT_EQ(sources(out), std::vector<std::string>{"adjtimex"});
  EXPECT_NE(m.chrony_error().find("506"), std::string::npos);
  EXPECT_EQ(m.last_error(), m.chrony_error());
  out.clear();
  clocks.raw_ns = 2000 * kMs;
  m.on_batch(1, out);
  EXPECT_EQ(sources(out), (std::vector<std::string>{"adjtimex", "chrony"}));
  EXPECT_TRUE(m.chrony_error().empty());
  EXPECT_TRUE(m.last_error().empty());
}

TEST(ClockMonitor, SampleAllReadsEverySourceNow) {
  FakeClocks clocks;
  ScriptedRunner runner;
  const auto chrony = ScriptedRunner::exited(0, fixture("chronyc_tracking_synchronised.csv"));
  const auto pmc = ScriptedRunner::exited(0, fixture("pmc_three_slave.txt"));
  runner.results = {chrony, pmc, chrony, pmc};
  MonitorOptions o;
  o.chrony_interval = std::chrono::hours(1);
  o.ptp_interval = std::chrono::hours(1);
  ClockMonitor m(o, clocks, &runner);
  std::vector<store::ClockSample> out;
  m.sample_all(9, out);
  m.sample_all(9, out);  // again at once: forced, not waiting for the intervals
  EXPECT_EQ(sources(out),
            (std::vector<std::string>{"adjtimex", "chrony", "ptp", "adjtimex", "chrony", "ptp"}));
  for (const auto& s : out) EXPECT_EQ(s.session_id, 9);
}

}  // namespace
}  // namespace m2mlat::sync
