// Clock steps from a kernel log's realtime stamps against its own printk (monotonic) stamps.
#include "m2mlat/analysis/kernel_log_steps.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace m2mlat::analysis::kernel_log_steps_test {

constexpr std::int64_t kRealtimeAtBoot = 1'780'303'400'000'000'000;  // ns
constexpr std::int64_t kMs = 1'000'000;

// A log of `lines` edges 1.3 s apart with printk delays of 20..200 us; the realtime clock slews at
// `slew_ppm` and is stepped by `step_ns` before line `step_line`.
using Log = LogStamps;
Log make_log(int lines, std::int64_t step_ns, int step_line, double slew_ppm = 0, std::int64_t apart_ms = 1'300) {
  Log log;
  for (int i = 0; i < lines; ++i) {
    const std::int64_t mono_ns = 1000'000 * kMs + i * apart_ms * kMs;  // uptime of the edge
    const auto slewed = static_cast<std::int64_t>(static_cast<double>(mono_ns) * slew_ppm * 1e-6);
    const std::int64_t delay_ns = 20'000 + (i * 7919 % 180) * 1000;
    log.realtime_ns.push_back(kRealtimeAtBoot + mono_ns + slewed + (i >= step_line ? step_ns : 0));
    log.log_time_us.push_back((mono_ns + delay_ns) / 1000);
  }
  return log;
}

TEST(KernelLogSteps, AStepForwardIsFoundBetweenItsLinesWithItsSize) {
  const auto log = make_log(40, 40 * kMs, 17);
  const auto steps = kernel_log_steps(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].at_ns, log.realtime_ns[17]);
  EXPECT_EQ(steps[0].earliest_ns, log.realtime_ns[17]);
  ASSERT_TRUE(steps[0].size_ns);
  // Within the bound it states, and the bound is the printk jitter (<= 180 us a side) plus slewing.
  EXPECT_LE(std::llabs(*steps[0].size_ns - 40 * kMs), steps[0].size_max_ns);
  EXPECT_LT(std::llabs(*steps[0].size_ns - 40 * kMs), 200'000);
  EXPECT_LT(steps[0].size_est_ns, 300'000);
  EXPECT_EQ(steps[0].origin, "kernel_log");
}

TEST(KernelLogSteps, AStepBackIsFoundToo) {
  const auto log = make_log(40, -40 * kMs, 25);
  const auto steps = kernel_log_steps(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].at_ns, log.realtime_ns[25]);
  EXPECT_LE(std::llabs(*steps[0].size_ns + 40 * kMs), steps[0].size_max_ns);
  EXPECT_LT(std::llabs(*steps[0].size_ns + 40 * kMs), 200'000);
}

// Steps of a few ms where the lines are seconds apart: the two windows span ~9 s, over which the
// kernel may slew 4.5 ms, but no single line pair can move 3 ms (once hidden below that allowance).
TEST(KernelLogSteps, AStepOfAFewMsBetweenLinesSecondsApartIsFound) {
  for (const std::int64_t size : {3 * kMs, -3 * kMs, 8 * kMs, -8 * kMs}) {
    const auto log = make_log(40, size, 20);
    const auto steps = kernel_log_steps(log.realtime_ns, log.log_time_us);
    ASSERT_EQ(steps.size(), 1u) << size;
    EXPECT_EQ(steps[0].at_ns, log.realtime_ns[20]);
    EXPECT_LE(std::llabs(*steps[0].size_ns - size), steps[0].size_max_ns);
    EXPECT_LT(std::llabs(*steps[0].size_ns - size), 200'000);
  }
}

TEST(KernelLogSteps, SlewingAndOneLatePrintkAreNoStep) {
  // 450 ppm is within the kernel's slewing: 0.6 ms between lines 1.3 s apart, 23 ms over the log.
  EXPECT_TRUE(kernel_log_steps(make_log(40, 0, 0, 450).realtime_ns, make_log(40, 0, 0, 450).log_time_us).empty());
  auto log = make_log(40, 0, 0);
  log.log_time_us[12] += 30'000;  // one message printed 30 ms late (console lock)
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  EXPECT_TRUE(clock.steps.empty());
  // Its two stamps disagree with the lines on both sides: its event is left out, not trusted.
  ASSERT_EQ(clock.left_out.size(), 1u);
  EXPECT_EQ(clock.left_out[0], (std::pair{std::size_t{12}, LineFault::outlier}));
}

TEST(KernelLogSteps, StampsThatAreNoClockGiveNoSteps) {
  auto log = make_log(40, 0, 0);
  for (std::size_t i = 0; i < log.log_time_us.size(); ++i)
    log.log_time_us[i] = static_cast<std::int64_t>(i) * 1'000'000;  // "[ 7.000000]": a line counter
  EXPECT_TRUE(kernel_log_steps(log.realtime_ns, log.log_time_us).empty());
}

TEST(KernelLogSteps, AFastSlewOverAFewLinesIsOneStep) {
  // A daemon catching up with a stepped reference: +15, +15, +10 ms over three lines.
  auto log = make_log(40, 15 * kMs, 17);
  for (std::size_t i = 18; i < log.realtime_ns.size(); ++i) log.realtime_ns[i] += 15 * kMs;
  for (std::size_t i = 19; i < log.realtime_ns.size(); ++i) log.realtime_ns[i] += 10 * kMs;
  const auto steps = kernel_log_steps(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_LT(std::llabs(*steps[0].size_ns - 40 * kMs), 200'000);
  EXPECT_EQ(steps[0].earliest_ns, log.realtime_ns[17]);
  EXPECT_EQ(steps[0].at_ns - *steps[0].size_ns, log.realtime_ns[19]);  // lines 17, 18 are flagged
  EXPECT_GT(steps[0].size_est_ns, steps[0].size_max_ns / 2);
}

TEST(KernelLogSteps, NothingIsSeenAcrossAReboot) {
  auto log = make_log(20, 0, 0);
  auto second = make_log(20, 5'000 * kMs, 0);  // another boot: uptime restarts, realtime moved on
  log.realtime_ns.insert(log.realtime_ns.end(), second.realtime_ns.begin(), second.realtime_ns.end());
  log.log_time_us.insert(log.log_time_us.end(), second.log_time_us.begin(), second.log_time_us.end());
  EXPECT_TRUE(kernel_log_steps(log.realtime_ns, log.log_time_us).empty());
}

// A daemon that slews far faster than 500 ppm (chrony without maxslewrate): d moves 8 ms ahead and
// back 6.5 s later at four places, then 9 ms ahead 45 s after the last move back (which that move
// then undoes by the rule: the running sum from it comes back to 1 ms, within half of it).
Log fast_slewing_log(std::int64_t step_ns, int step_line) {
  auto log = make_log(200, step_ns, step_line);
  const auto shift = [&](int from, std::int64_t by) {
    for (std::size_t i = static_cast<std::size_t>(from); i < log.realtime_ns.size(); ++i) log.realtime_ns[i] += by;
  };
  for (int at : {20, 60, 100, 140}) {
    shift(at, 8 * kMs);
    shift(at + 5, -8 * kMs);
  }
  shift(180, 9 * kMs);
  return log;
}

TEST(KernelLogSteps, AClockSlewingFasterThanTheBoundGivesNoSteps) {
  const auto log = fast_slewing_log(0, 0);
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  EXPECT_TRUE(clock.steps.empty());
  EXPECT_EQ(clock.limits.fast_slew_places, 9u);
  // Twice the largest excursion (9 ms, measured by the windows' medians to within 0.5 ms).
  EXPECT_NEAR(static_cast<double>(clock.limits.hidden_below_ns), 18.0 * kMs, 1.0 * kMs);
  EXPECT_NE(fast_slewing_note(clock.limits.fast_slew_places, clock.limits.hidden_below_ns).find("at 9 places"), std::string::npos);
}

TEST(KernelLogSteps, AGenuineStepStandsOutOfFastSlewing) {
  const auto log = fast_slewing_log(40 * kMs, 120);
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(clock.steps.size(), 1u);
  EXPECT_EQ(clock.steps[0].at_ns, log.realtime_ns[120]);
  ASSERT_TRUE(clock.steps[0].size_ns);
  EXPECT_LT(std::llabs(*clock.steps[0].size_ns - 40 * kMs), 200'000);
  EXPECT_EQ(clock.limits.fast_slew_places, 9u);
  // With the bound held, the same log's slewing would be nine steps: the rule is what drops them.
  KernelLogStepOptions trusting;
  trusting.fast_places_min = 1000;
  EXPECT_EQ(kernel_log_steps(log.realtime_ns, log.log_time_us, trusting).size(), 10u);
}

// The lines kernel_log_clock leaves out, as indices, and their reasons.
std::vector<std::size_t> left_out_lines(const KernelLogClock& clock, LineFault why) {
  std::vector<std::size_t> out;
  for (const auto& [line, fault] : clock.left_out)
    if (fault == why) out.push_back(line);
  return out;
}

TEST(KernelLogSteps, ALineOfAnotherClockIsAnOutlierAndMovesNothing) {
  for (const std::size_t at : {std::size_t{0}, std::size_t{1}, std::size_t{20}, std::size_t{39}}) {
    for (const std::int64_t off : {-37'000'000 * kMs, 90 * kMs, -kRealtimeAtBoot}) {  // hours, 90 ms, ktime_get_ns
      auto log = make_log(40, 0, 0);
      log.realtime_ns[at] += off;
      const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
      EXPECT_TRUE(clock.steps.empty()) << at << " " << off;
      EXPECT_EQ(left_out_lines(clock, LineFault::outlier), std::vector<std::size_t>{at}) << at << " " << off;
    }
  }
  // The same beside a genuine step: the step is found with its size, the outlier alone left out.
  auto log = make_log(40, 40 * kMs, 20);
  log.realtime_ns[21] -= 37'000'000 * kMs;
  log.log_time_us[10] += 40'000'000'000;  // a printk stamp far off: the same line fault
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(clock.steps.size(), 1u);
  EXPECT_EQ(clock.steps[0].at_ns, log.realtime_ns[20]);
  EXPECT_LT(std::llabs(*clock.steps[0].size_ns - 40 * kMs), 200'000);
  EXPECT_EQ(left_out_lines(clock, LineFault::outlier), (std::vector<std::size_t>{10, 21}));
}

TEST(KernelLogSteps, TwoLinesAtALevelOfTheirOwnAreNoStep) {
  auto log = make_log(40, 0, 0);
  log.realtime_ns[15] += 5'000 * kMs;
  log.realtime_ns[16] += 5'000 * kMs;
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  EXPECT_TRUE(clock.steps.empty());
  EXPECT_EQ(left_out_lines(clock, LineFault::outlier), (std::vector<std::size_t>{15, 16}));
  // Three lines make a level: two steps, there and back (and nothing left out).
  log.realtime_ns[17] += 5'000 * kMs;
  const auto three = kernel_log_clock(log.realtime_ns, log.log_time_us);
  EXPECT_EQ(three.steps.size(), 2u);
  EXPECT_TRUE(three.left_out.empty());
}

// A log from boot: `before` edges 3..30 s after boot on a clock not yet set (`unset_ns` from the
// right time), the clock set at 45 s, then the run from 1000 s of uptime.
Log boot_log(int before, std::int64_t unset_ns) {
  auto run = make_log(40, 0, 0);
  Log log;
  for (int i = 0; i < before; ++i) {
    const std::int64_t mono_ns = (3'000 + i * 2'500) * kMs;
    log.realtime_ns.push_back(kRealtimeAtBoot + mono_ns + unset_ns);
    log.log_time_us.push_back(mono_ns / 1000 + 50);
  }
  log.realtime_ns.insert(log.realtime_ns.end(), run.realtime_ns.begin(), run.realtime_ns.end());
  log.log_time_us.insert(log.log_time_us.end(), run.log_time_us.begin(), run.log_time_us.end());
  return log;
}

TEST(KernelLogSteps, EdgesBeforeTheFirstSynchronisationAreLeftOutAndShiftNothing) {
  for (const int before : {1, 2, 5}) {
    for (const std::int64_t unset : {-kRealtimeAtBoot, -3 * 86'400'000 * kMs, 2'000 * kMs}) {  // 1970, fake-hwclock, an RTC
      const auto log = boot_log(before, unset);
      const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
      EXPECT_TRUE(clock.steps.empty()) << before << " " << unset;  // the first synchronisation is no step
      std::vector<std::size_t> want(static_cast<std::size_t>(before));
      for (std::size_t i = 0; i < want.size(); ++i) want[i] = i;
      EXPECT_EQ(left_out_lines(clock, LineFault::before_sync), want) << before << " " << unset;
      EXPECT_TRUE(left_out_lines(clock, LineFault::outlier).empty());
    }
  }
  // A board that never set its clock: every line counts from 1970.
  auto never = make_log(40, 0, 0);
  for (auto& t : never.realtime_ns) t -= kRealtimeAtBoot;
  EXPECT_EQ(left_out_lines(kernel_log_clock(never.realtime_ns, never.log_time_us), LineFault::before_sync).size(), 40u);
}

TEST(KernelLogSteps, AStepLongAfterBootIsCorrectedNotTakenForTheFirstSynchronisation) {
  auto log = boot_log(4, -3 * 86'400'000 * kMs);
  for (std::size_t i = 24; i < log.realtime_ns.size(); ++i) log.realtime_ns[i] += 3'600'000 * kMs;  // +1 h at line 24
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  ASSERT_EQ(clock.steps.size(), 1u);
  EXPECT_EQ(clock.steps[0].at_ns, log.realtime_ns[24]);
  EXPECT_LT(std::llabs(*clock.steps[0].size_ns - 3'600'000 * kMs), 200'000);
  EXPECT_EQ(left_out_lines(clock, LineFault::before_sync), (std::vector<std::size_t>{0, 1, 2, 3}));
}

TEST(KernelLogSteps, LeftOutLinesAreStoredAsRangesThatHoldNoKeptStamp) {
  auto log = boot_log(3, -3 * 86'400'000 * kMs);
  log.realtime_ns[20] -= 37'000'000 * kMs;
  const auto clock = kernel_log_clock(log.realtime_ns, log.log_time_us);
  const auto runs = unknown_clock_runs(log.realtime_ns, clock.left_out);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0], (store::UnknownClock{log.realtime_ns[0], log.realtime_ns[2], 3, "before_sync"}));
  EXPECT_EQ(runs[1], (store::UnknownClock{log.realtime_ns[20], log.realtime_ns[20], 1, "outlier"}));
  // Through a clock sample and back, as a store keeps them.
  EXPECT_EQ(store::unknown_clock_of(store::unknown_clock_sample(runs[0])), runs[0]);
  EXPECT_FALSE(store::clock_step_of(store::unknown_clock_sample(runs[0])));
}

// The other board stepped by `size` before line 20 of a log of `lines` lines (1.3 s apart): its step
// as kernel_log_clock gives it, stamped on this board's timescale.
store::ClockStep other_step(const Log& log, std::int64_t size) {
  store::ClockStep step;
  step.size_ns = size;
  step.earliest_ns = step.at_ns = log.realtime_ns[20] + size;
  step.size_max_ns = 300'000;
  step.size_est_ns = 130'000;
  step.origin = "kernel_log";
  return step;
}

// This board's daemon slews at 500 ppm onto the other's new timescale from 4 s after line 20.
Log follower_log(int lines, std::int64_t size, std::int64_t apart_ms = 1'300) {
  auto log = make_log(lines, 0, 0, 0, apart_ms);
  const std::int64_t from = log.realtime_ns[20] + 4'000 * kMs;
  for (auto& t : log.realtime_ns) {
    const std::int64_t slewed = t > from ? (t - from) / 2000 : 0;  // 500 ppm
    t += size > 0 ? std::min(slewed, size) : std::max(-slewed, size);
  }
  return log;
}

TEST(KernelLogFollowed, AFollowerSlewingOntoTheOthersStepTakesItOver) {
  for (const std::int64_t size : {40 * kMs, -40 * kMs, 6 * kMs}) {
    const auto log = follower_log(160, size);
    const auto step = other_step(log, size);
    const auto follows = kernel_log_followed(std::vector{step}, {}, log.realtime_ns, log.log_time_us);
    ASSERT_EQ(follows.size(), 1u) << size;
    EXPECT_EQ(follows[0].origin, "followed");
    EXPECT_EQ(follows[0].size_ns, size);
    EXPECT_EQ(follows[0].earliest_ns, step.earliest_ns);
    // Back in step (within |S| / 16, at least 1 ms) at a line after the slew's 4 s + |S| / 500 ppm:
    // the lines before it are flagged, the rest corrected by S.
    const std::int64_t back_at = follows[0].at_ns - size;
    const auto back = std::find(log.realtime_ns.begin(), log.realtime_ns.end(), back_at);
    ASSERT_NE(back, log.realtime_ns.end());
    const std::int64_t done = log.realtime_ns[20] + 4'000 * kMs + std::llabs(size) * 2000;
    EXPECT_GE(back_at, done - std::max<std::int64_t>(std::llabs(size) / 16, kMs) * 2000 - 1'300 * kMs);
    EXPECT_LE(back_at, done + 1'300 * kMs);
    EXPECT_LE(follows[0].size_max_ns, step.size_max_ns + 2 * std::max<std::int64_t>(std::llabs(size) / 16, kMs) + 400'000);
  }
}

TEST(KernelLogFollowed, ABoardThatStaysOrStepsItselfTakesNothingOver) {
  // Autonomous: its own daemon keeps it where it was.
  const auto still = make_log(160, 0, 0);
  EXPECT_TRUE(kernel_log_followed(std::vector{other_step(still, 40 * kMs)}, {}, still.realtime_ns, still.log_time_us).empty());
  // Its own step (found by kernel_log_clock) is its own correction, no follow.
  const auto stepped = make_log(160, 40 * kMs, 22);
  const auto own = kernel_log_steps(stepped.realtime_ns, stepped.log_time_us);
  ASSERT_EQ(own.size(), 1u);
  EXPECT_TRUE(kernel_log_followed(std::vector{other_step(stepped, 40 * kMs)}, own, stepped.realtime_ns,
                                  stepped.log_time_us)
                  .empty());
  // One late printk after the step moves one line's d by 30 ms: no follow either.
  auto late = make_log(160, 0, 0);
  late.log_time_us[23] += 30'000;
  EXPECT_TRUE(
      kernel_log_followed(std::vector{other_step(late, -40 * kMs)}, {}, late.realtime_ns, late.log_time_us).empty());
}

TEST(KernelLogFollowed, ALatePrintkDuringTheSlewHidesNoFollow) {
  auto log = follower_log(160, -40 * kMs);
  log.log_time_us[23] += 30'000;
  EXPECT_EQ(kernel_log_followed(std::vector{other_step(log, -40 * kMs)}, {}, log.realtime_ns, log.log_time_us).size(), 1u);
}

TEST(KernelLogFollowed, ALogEndingMidSlewIsFlaggedToItsEnd) {
  // 300 ms at 500 ppm takes 10 minutes; the log ends 3 minutes after the step.
  const auto log = follower_log(160, 300 * kMs);
  const auto follows = kernel_log_followed(std::vector{other_step(log, 300 * kMs)}, {}, log.realtime_ns, log.log_time_us);
  ASSERT_EQ(follows.size(), 1u);
  EXPECT_GT(follows[0].at_ns, log.realtime_ns.back() + 300 * kMs);
  // Lines 2.6 s apart: slewing 1.3 ms a line for most of the log, more than the printk jitter's 1 ms
  // limit in every jump (once read as stamps that follow no clock, and the follow went unseen).
  const auto sparse = follower_log(160, -250 * kMs, 2'600);
  const auto sparse_follows =
      kernel_log_followed(std::vector{other_step(sparse, -250 * kMs)}, {}, sparse.realtime_ns, sparse.log_time_us);
  ASSERT_EQ(sparse_follows.size(), 1u);
  EXPECT_GT(sparse_follows[0].at_ns, sparse.realtime_ns.back());
}

}  // namespace m2mlat::analysis::kernel_log_steps_test
