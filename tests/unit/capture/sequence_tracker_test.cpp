// Gap detection in kernel sequence numbers, and the refractory gate.
#include "m2mlat/capture/sequence_tracker.hpp"

#include <gtest/gtest.h>

#include "m2mlat/capture/refractory_gate.hpp"

namespace m2mlat::capture {
namespace {

TEST(SequenceTracker, AFreshRequestStartsAtOneSoEarlyLossesShow) {
  SequenceTracker t(1, 32);
  const auto first = t.observe(4);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->first, 1u);
  EXPECT_EQ(first->count, 3u);
  EXPECT_FALSE(t.observe(5).has_value());
  const auto gap = t.observe(9);
  ASSERT_TRUE(gap.has_value());
  EXPECT_EQ(gap->first, 6u);
  EXPECT_EQ(gap->count, 3u);
  EXPECT_EQ(t.missing_total(), 6u);
}

TEST(SequenceTracker, JoiningMidwayStartsAtTheFirstValue) {
  SequenceTracker t(0, 64);
  EXPECT_FALSE(t.observe(1000).has_value());
  EXPECT_FALSE(t.observe(1001).has_value());
  const auto gap = t.observe(1010);
  ASSERT_TRUE(gap.has_value());
  EXPECT_EQ(gap->first, 1002u);
  EXPECT_EQ(gap->count, 8u);
}

TEST(SequenceTracker, The32BitWrapIsNoGapAndRepeatsAreNoLoss) {
  SequenceTracker t(0xFFFFFFFEu, 32);
  EXPECT_FALSE(t.observe(0xFFFFFFFEu).has_value());
  EXPECT_FALSE(t.observe(0xFFFFFFFFu).has_value());
  EXPECT_FALSE(t.observe(0).has_value());
  EXPECT_FALSE(t.observe(1).has_value());
  EXPECT_FALSE(t.observe(1).has_value());  // a repeat
  EXPECT_EQ(t.missing_total(), 0u);
  const auto gap = t.observe(4);
  ASSERT_TRUE(gap.has_value());
  EXPECT_EQ(gap->first, 2u);
  EXPECT_EQ(gap->count, 2u);
}

TEST(RefractoryGate, MeasuresFromTheLastKeptEdge) {
  using core::TimePoint;
  RefractoryGate gate(std::chrono::milliseconds(10));
  const auto t = [](std::int64_t ms) { return TimePoint::from_ns(core::Clock::realtime, ms * 1'000'000); };
  EXPECT_TRUE(gate.admit(t(0)));
  EXPECT_FALSE(gate.admit(t(3)));
  EXPECT_FALSE(gate.admit(t(9)));  // 9 ms after the kept edge, though 6 after the last bounce
  EXPECT_TRUE(gate.admit(t(10)));  // exactly the period: kept
  EXPECT_FALSE(gate.admit(t(19)));
  EXPECT_EQ(gate.suppressed(), 3u);
  RefractoryGate none;
  EXPECT_TRUE(none.admit(t(0)));
  EXPECT_TRUE(none.admit(t(0)));
}

}  // namespace
}  // namespace m2mlat::capture
