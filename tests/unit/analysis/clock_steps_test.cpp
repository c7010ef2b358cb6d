// One board's events after its clock steps: corrected by a known size onto the timescale before the
// step, placed by the recording order when a step back makes stamps overlap, marked unknown after a
// step of unknown size until a synchronised sample says the clock is good again.
#include "m2mlat/analysis/clock_steps.hpp"

#include "m2mlat/analysis/scenario_result.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace m2mlat::analysis::clock_steps_test {

constexpr std::int64_t kT0 = 1'780'304'400'000'000'000;
constexpr std::int64_t kMs = 1'000'000;

store::ClockStep known(std::int64_t at_ns, std::int64_t size_ns, std::int64_t max_ns = 100, std::int64_t est_ns = 50) {
  return {at_ns, at_ns, size_ns, max_ns, est_ns, "sim"};
}

// Events every 100 ms of true time (t = kT0 + k * 100 ms), the clock stepped by `size` at true
// kT0 + 1 s: what the board stamped, in recording order.
store::Timestamps stamped(std::int64_t size, int count = 20) {
  store::Timestamps side;
  for (int k = 0; k < count; ++k) {
    const std::int64_t truth = kT0 + k * 100 * kMs + 5 * kMs;
    side.t_ns.push_back(truth + (truth >= kT0 + 1000 * kMs ? size : 0));
  }
  return side;
}

std::vector<std::int64_t> truth(int count = 20) {
  std::vector<std::int64_t> out;
  for (int k = 0; k < count; ++k) out.push_back(kT0 + k * 100 * kMs + 5 * kMs);
  return out;
}

TEST(ClockSteps, AKnownStepForwardIsTakenBackOut) {
  auto side = stamped(40 * kMs);
  const std::vector<store::ClockStep> steps{known(kT0 + 1040 * kMs, 40 * kMs)};
  const auto marks = correct_side(side, steps, {});
  EXPECT_EQ(side.t_ns, truth());
  EXPECT_EQ(marks.corrected, 10u);
  EXPECT_EQ(marks.unknown, 0u);
  EXPECT_EQ(marks.at(9), StepMark::none);
  EXPECT_EQ(marks.at(10), StepMark::corrected);
  EXPECT_EQ(marks.bound(10).max_ns, 100);
  EXPECT_EQ(marks.bound(10).est_ns, 50);
  EXPECT_EQ(marks.bound(9).max_ns, 0);  // not corrected: no bounds
  EXPECT_EQ(marks.first_after, (std::vector<std::int64_t>{10}));
}

TEST(ClockSteps, AStepBackIsPlacedByTheRecordingOrder) {
  // -140 ms: the events at true 0.905 s (stamped 0.905) and 1.005 s (stamped 0.865) overlap.
  auto side = stamped(-140 * kMs);
  const std::vector<store::ClockStep> steps{known(kT0 + 860 * kMs, -140 * kMs)};
  const auto marks = correct_side(side, steps, {});
  EXPECT_EQ(side.t_ns, truth());
  EXPECT_EQ(marks.corrected, 10u);
  EXPECT_EQ(marks.unknown, 0u);
}

TEST(ClockSteps, StampsThatCouldLieOnEitherSideAreMarkedNotGuessed) {
  // The step's time is known only to a 300 ms window (a monitor reading late): a +40 ms step,
  // stamps in [0.74 s, 1.04 s - 40 ms) of the new timescale could be before or after it.
  auto side = stamped(40 * kMs);
  store::ClockStep step = known(kT0 + 1040 * kMs, 40 * kMs);
  step.earliest_ns = kT0 + 740 * kMs;
  const auto marks = correct_side(side, std::vector{step}, {});
  EXPECT_EQ(marks.at(7), StepMark::none);  // 0.705: before the window
  EXPECT_EQ(marks.at(8), StepMark::unknown);
  EXPECT_EQ(marks.at(9), StepMark::unknown);
  EXPECT_EQ(marks.at(10), StepMark::corrected);
  EXPECT_EQ(marks.unknown, 2u);
  EXPECT_EQ(side.t_ns[10], truth()[10]);
}

TEST(ClockSteps, AfterAStepOfUnknownSizeUntilTheClockIsGoodAgain) {
  auto side = stamped(40 * kMs);
  store::ClockStep step{kT0 + 1040 * kMs, kT0 + 1040 * kMs, std::nullopt, store::kUnknownSize,
                        store::kUnknownSize, "adjtimex"};
  store::ClockSample good;
  good.time = core::TimePoint::from_ns(core::Clock::realtime, kT0 + 1500 * kMs);
  good.source = "chrony";
  good.synchronised = true;
  const auto marks = correct_side(side, std::vector{step}, std::vector{good});
  EXPECT_EQ(marks.unknown, 5u);  // 1.045 .. 1.445 s; from 1.545 s the clock is known good
  EXPECT_EQ(marks.at(9), StepMark::none);
  EXPECT_EQ(marks.at(10), StepMark::unknown);
  EXPECT_EQ(marks.at(14), StepMark::unknown);
  EXPECT_EQ(marks.at(15), StepMark::none);
  EXPECT_EQ(side.t_ns, stamped(40 * kMs).t_ns);  // nothing corrected
}

TEST(ClockSteps, EveryStepRecordReadsBack) {
  // The current record, and an older monitor record (error fields = |step|).
  const auto step = known(kT0, -40 * kMs, 800, 400);
  const auto back = store::clock_step_of(store::step_clock_sample(step));
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, step);
  store::ClockSample old;
  old.time = core::TimePoint::from_ns(core::Clock::realtime, kT0);
  old.source = "step";
  old.offset_ns = old.max_error_ns = old.est_error_ns = 3'000'000;
  old.detail_json = R"({"from_ns":1,"to_ns":2,"step_ns":3000000,"unexplained_ns":2999000})";
  const auto legacy = store::clock_step_of(old);
  ASSERT_TRUE(legacy);
  EXPECT_EQ(legacy->size_ns, 3'000'000);
  EXPECT_EQ(legacy->size_max_ns, 1000);
  EXPECT_EQ(legacy->origin, "monitor");
  store::ClockSample chrony;
  chrony.source = "chrony";
  EXPECT_FALSE(store::clock_step_of(chrony));
}

store::ClockSample daemon_sample(std::int64_t t_ns, std::int64_t offset_ns, std::int64_t est_ns = 200'000) {
  store::ClockSample s;
  s.time = core::TimePoint::from_ns(core::Clock::realtime, t_ns);
  s.source = "chrony";
  s.offset_ns = offset_ns;
  s.est_error_ns = est_ns;
  s.max_error_ns = 3 * est_ns;
  s.synchronised = true;
  return s;
}

TEST(ClockSteps, ABoardWhoseDaemonFollowsTheSteppedOneTakesTheStepAfterItsSlew) {
  constexpr std::int64_t kS = 1'000'000'000;
  const std::vector<store::ClockStep> stepped{known(kT0 + 60 * kS, 40 * kMs, 100, 50)};
  std::vector<store::ClockSample> follower;
  for (int k = 0; k < 6; ++k) follower.push_back(daemon_sample(kT0 + k * 10 * kS, (k % 2 ? 1 : -1) * 100'000));
  // After the step: behind by the step, overshooting, then back within 2.5 ms twice in a row.
  for (auto [k, offset] : {std::pair{6, -30 * kMs}, {7, 4 * kMs}, {8, 2 * kMs}, {9, kMs / 2}, {10, 0}})
    follower.push_back(daemon_sample(kT0 + k * 10 * kS, offset));
  const auto taken = followed_steps(stepped, follower);
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].size_ns, 40 * kMs);
  EXPECT_EQ(taken[0].earliest_ns, kT0 + 60 * kS);
  EXPECT_EQ(taken[0].at_ns - 40 * kMs, kT0 + 80 * kS);  // flagged until the 80 s sample, corrected after
  EXPECT_EQ(taken[0].size_max_ns, 100 + 2 * 2 * kMs);
  EXPECT_EQ(taken[0].origin, "followed");

  // A daemon with its own reference does not notice the other board's step: nothing taken over.
  std::vector<store::ClockSample> independent(follower.begin(), follower.begin() + 6);
  for (int k = 6; k < 11; ++k) independent.push_back(daemon_sample(kT0 + k * 10 * kS, 150'000));
  EXPECT_TRUE(followed_steps(stepped, independent).empty());
}

// A scenario: causes every 100 ms, effects 30 ms after each on the stepped board.
ScenarioInput scenario(std::int64_t size) {
  ScenarioInput input;
  input.scenario = "s";
  input.cause_ref = {"operator", "wheel"};
  input.effect_ref = {"vehicle", "wheel"};
  input.cause.t_ns = truth();
  input.effect = stamped(size);
  for (auto& t : input.effect.t_ns) t += 30 * kMs;
  return input;
}

TEST(ClockSteps, CorrectedPairsStayInTheStatisticsFlaggedOnesLeave) {
  for (const bool size_known : {true, false}) {
    auto input = scenario(40 * kMs);
    store::ClockStep step = known(kT0 + 1040 * kMs, 40 * kMs);
    if (!size_known) step.size_ns.reset();
    const std::vector<store::ClockSample> effect_samples{store::step_clock_sample(step)};
    auto steps = correct_scenario(input, {}, effect_samples);
    const auto result = analyse(std::move(input), std::move(steps), {}, {});
    ASSERT_EQ(result.match.pairs.size(), 20u) << size_known;
    EXPECT_EQ(result.pairs_marked(StepMark::corrected), size_known ? 10u : 0u);
    EXPECT_EQ(result.pairs_marked(StepMark::unknown), size_known ? 0u : 10u);
    EXPECT_EQ(result.summary.n, size_known ? 20u : 10u);
    // What reaches the statistics is the true 30 ms, never 70 ms.
    for (const auto latency : result.latencies_ns()) EXPECT_EQ(latency, 30 * kMs);
  }
}

}  // namespace m2mlat::analysis::clock_steps_test
