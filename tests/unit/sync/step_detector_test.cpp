// Step detection: a change of realtime - monotonic_raw beyond what the rate correction explains.
#include "m2mlat/sync/step_detector.hpp"
#include "m2mlat/store/clock_step.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace m2mlat::sync {
namespace {

constexpr std::int64_t kRealtimeAtRawZero = 1'795'269'000'000'000'000;  // realtime at raw = 0, ns
constexpr std::int64_t kSecond = 1'000'000'000;

ClockPair pair(std::int64_t raw_ns, std::int64_t realtime_offset_ns = 0) {
  return ClockPair{kRealtimeAtRawZero + raw_ns + realtime_offset_ns, raw_ns, 200};
}

TEST(StepDetector, NoStepWhileTheClocksRunTogether) {
  StepDetector d;
  EXPECT_FALSE(d.observe(pair(0), 0));
  for (int i = 1; i <= 100; ++i) EXPECT_FALSE(d.observe(pair(i * kSecond), 0)) << i;
}

TEST(StepDetector, AForwardAndABackwardStep) {
  StepDetector d;
  d.observe(pair(0), 0);
  const auto forward = d.observe(pair(kSecond, 5'000'000), 0);  // +5 ms
  ASSERT_TRUE(forward);
  EXPECT_EQ(forward->step_ns, 5'000'000);
  EXPECT_EQ(forward->to_ns, kRealtimeAtRawZero + kSecond + 5'000'000);
  EXPECT_EQ(forward->from_ns, kRealtimeAtRawZero + kSecond);
  EXPECT_EQ(forward->unexplained_ns,
            5'000'000 - 500'000 - 200);                      // less 500 ppm of 1 s and the pairing window
  EXPECT_FALSE(d.observe(pair(2 * kSecond, 5'000'000), 0));  // stays stepped: no new step
  const auto back = d.observe(pair(3 * kSecond, -20'000'000), 0);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->step_ns, -25'000'000);
}

TEST(StepDetector, TheFrequencyCorrectionExplainsASlowDrift) {
  // 1000 ppm (chrony slewing) over 10 s moves realtime by 10 ms against raw: not a step at 1000 ppm...
  StepDetector d;
  d.observe(pair(0), 1000);
  EXPECT_FALSE(d.observe(pair(10 * kSecond, 10'000'000), 1000));
  // ...but it is one when the kernel claims no correction (and the tolerance is 500 ppm: 5 ms of 10).
  StepDetector strict;
  strict.observe(pair(0), 0);
  const auto s = strict.observe(pair(10 * kSecond, 10'000'000), 0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->unexplained_ns, 10'000'000 - 5'000'000 - 200);
}

TEST(StepDetector, ThresholdIsConfigurable) {
  StepDetector d(StepOptions{std::chrono::microseconds(100), 0});
  d.observe(pair(0), 0);
  EXPECT_FALSE(d.observe(pair(kSecond, 90'000), 0));
  EXPECT_TRUE(d.observe(pair(2 * kSecond, 300'000), 0));
}

TEST(StepDetector, SampleHasTheDetail) {
  StepDetector d;
  d.observe(pair(0), 0);
  const auto step = d.observe(pair(kSecond, -3'000'000), 0);
  ASSERT_TRUE(step);
  const auto s = step_sample(*step);
  EXPECT_EQ(s.source, "step");
  EXPECT_EQ(s.time.ns(), kRealtimeAtRawZero + kSecond - 3'000'000);
  EXPECT_EQ(s.offset_ns, -3'000'000);
  // The error fields hold the size's uncertainty (what the rates and windows explain), not |step|.
  EXPECT_EQ(s.max_error_ns, step->explained_ns);
  EXPECT_LT(s.max_error_ns, 1'000'000);
  EXPECT_FALSE(s.synchronised);
  const auto record = store::clock_step_of(s);
  ASSERT_TRUE(record);
  EXPECT_EQ(record->size_ns, -3'000'000);
  EXPECT_EQ(record->at_ns, s.time.ns());
  EXPECT_EQ(record->earliest_ns, s.time.ns() - kSecond - step->explained_ns);
  EXPECT_EQ(record->origin, "monitor");
  const auto j = nlohmann::json::parse(s.detail_json);
  EXPECT_EQ(j["from_ns"], kRealtimeAtRawZero + kSecond);
  EXPECT_EQ(j["to_ns"], kRealtimeAtRawZero + kSecond - 3'000'000);
  EXPECT_EQ(j["step_ns"], -3'000'000);
}

}  // namespace
}  // namespace m2mlat::sync
