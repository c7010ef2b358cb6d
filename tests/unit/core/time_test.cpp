#include "m2mlat/core/time.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/event.hpp"

using namespace m2mlat::core;
using namespace std::chrono_literals;

TEST(Time, SubtractSameClock) {
  const auto a = TimePoint::from_ns(Clock::realtime, 1'762'872'545'550'296'135);
  const auto b = TimePoint::from_ns(Clock::realtime, 1'762'872'546'417'585'462);
  EXPECT_EQ((b - a).count(), 867'289'327);
  EXPECT_EQ(format_ms(b - a), "867.289327");
}

TEST(Time, SubtractDifferentClocksThrows) {
  const auto a = TimePoint::from_ns(Clock::realtime, 1);
  const auto b = TimePoint::from_ns(Clock::monotonic, 2);
  EXPECT_THROW((void)(b - a), Error);
}

TEST(Time, OneNanosecondSurvivesTextRoundTrip) {
  // 2^53 + 1 ns is not representable as a double; the text path must keep it exactly.
  const std::int64_t ns = 1'762'872'545'550'296'135;
  std::int64_t back = 0;
  ASSERT_TRUE(parse_seconds(format_seconds(ns), back));
  EXPECT_EQ(back, ns);
  ASSERT_TRUE(parse_seconds(format_seconds(ns + 1), back));
  EXPECT_EQ(back, ns + 1);
  EXPECT_EQ(format_seconds(-1), "-0.000000001");
}

TEST(Time, ParseSeconds) {
  std::int64_t ns = 0;
  EXPECT_TRUE(parse_seconds("12", ns));
  EXPECT_EQ(ns, 12'000'000'000);
  EXPECT_TRUE(parse_seconds("-0.5", ns));
  EXPECT_EQ(ns, -500'000'000);
  EXPECT_FALSE(parse_seconds("1.0000000001", ns));  // 10 decimals: would need rounding
  EXPECT_FALSE(parse_seconds("", ns));
  EXPECT_FALSE(parse_seconds("1e9", ns));
  EXPECT_FALSE(parse_seconds("99999999999999999999", ns));
  EXPECT_TRUE(parse_ms("867.289327", ns));
  EXPECT_EQ(ns, 867'289'327);
}

TEST(Time, ParseDuration) {
  EXPECT_EQ(parse_duration("800ms"), 800ms);
  EXPECT_EQ(parse_duration("3s"), 3s);
  EXPECT_EQ(parse_duration("1.5s"), 1500ms);
  EXPECT_EQ(parse_duration("250us"), 250us);
  EXPECT_EQ(parse_duration("10ns"), 10ns);
  EXPECT_EQ(parse_duration("2min"), 120s);
  EXPECT_EQ(parse_duration("170", 1'000'000), 170ms);
  EXPECT_THROW(parse_duration("170"), Error);
  EXPECT_THROW(parse_duration("fast"), Error);
  EXPECT_EQ(format_duration(812345678ns), "812.345 ms");
}

TEST(Event, ChannelRefAndRoles) {
  EXPECT_EQ(parse_channel_ref("vehicle/wheel"), (ChannelRef{"vehicle", "wheel"}));
  EXPECT_EQ(parse_channel_ref("operator"), (ChannelRef{"operator", "wheel"}));
  EXPECT_EQ(parse_role("operator"), Role::cause);
  EXPECT_EQ(parse_role("vehicle"), Role::effect);
  EXPECT_THROW(parse_role("pilot"), Error);
  EXPECT_EQ(parse_clock("realtime"), Clock::realtime);
}
