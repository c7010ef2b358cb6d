// NodeTracker: the state machine (unreachable until contact, ok, stale after --stale-after,
// unreachable after a failure), the 10 s event rate, and the status fields, driven by a fake clock.
#include "m2mlat/collect/health.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace m2mlat::collect {
namespace {

constexpr std::int64_t kS = 1'000'000'000;
constexpr std::int64_t kT0 = 1'700'000'000 * kS;

TEST(NodeTracker, IsUnreachableUntilTheFirstContact) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  const auto h = t.snapshot(kT0);
  EXPECT_EQ(h.state, NodeState::unreachable);
  EXPECT_EQ(h.url, "http://a:1");
  EXPECT_EQ(h.last_contact_ns, 0);
  EXPECT_EQ(h.events_per_s, 0.0);
}

TEST(NodeTracker, GoesStaleWithoutContactAndUnreachableOnFailure) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  t.contact(kT0);
  EXPECT_EQ(t.snapshot(kT0 + 3 * kS).state, NodeState::ok);
  EXPECT_EQ(t.snapshot(kT0 + 3 * kS + 1).state, NodeState::stale);
  t.failed("GET http://a:1/v1/status: cannot connect", kT0 + 4 * kS);
  auto h = t.snapshot(kT0 + 4 * kS);
  EXPECT_EQ(h.state, NodeState::unreachable);
  EXPECT_EQ(h.last_error, "GET http://a:1/v1/status: cannot connect");
  EXPECT_EQ(h.last_contact_ns, kT0);
  t.contact(kT0 + 5 * kS);
  h = t.snapshot(kT0 + 5 * kS);
  EXPECT_EQ(h.state, NodeState::ok);
  EXPECT_TRUE(h.last_error.empty());
}

TEST(NodeTracker, AveragesTheEventRateOverTheLastTenSeconds) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  t.contact(kT0);
  // 100 events every second for 20 s.
  for (int i = 1; i <= 20; ++i) {
    t.contact(kT0 + i * kS);
    t.stored(100, 100 * i, kT0 + i * kS);
  }
  auto h = t.snapshot(kT0 + 20 * kS);
  EXPECT_DOUBLE_EQ(h.events_per_s, 100.0);  // 10 batches of 100 in the window (10 s, 20 s]
  EXPECT_EQ(h.events, 2000u);
  EXPECT_EQ(h.cursor_seq, 2000);
  // Nothing more: the rate falls as the window empties.
  EXPECT_DOUBLE_EQ(t.snapshot(kT0 + 25 * kS).events_per_s, 50.0);
  EXPECT_DOUBLE_EQ(t.snapshot(kT0 + 31 * kS).events_per_s, 0.0);
}

TEST(NodeTracker, UsesTheTimeSinceTheFirstContactBeforeTenSeconds) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  t.contact(kT0);
  t.stored(400, 400, kT0 + kS);
  EXPECT_DOUBLE_EQ(t.snapshot(kT0 + 2 * kS).events_per_s, 200.0);
  // Within the first second the divisor is 1 s, not less.
  NodeTracker u("http://a:1", std::chrono::seconds(3));
  u.contact(kT0);
  u.stored(50, 50, kT0 + 1000);
  EXPECT_DOUBLE_EQ(u.snapshot(kT0 + 2000).events_per_s, 50.0);
}

TEST(NodeTracker, KeepsTheAgentsStatus) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  t.status("vehicle", core::Role::effect, 7, 1234, ClockState{-250, 12'000, true}, kT0);
  auto h = t.snapshot(kT0);
  EXPECT_EQ(h.state, NodeState::ok);
  EXPECT_EQ(h.node, "vehicle");
  EXPECT_EQ(h.role, core::Role::effect);
  EXPECT_EQ(h.lost, 7u);
  EXPECT_EQ(h.agent_last_seq, 1234);
  EXPECT_TRUE(h.has_clock);
  EXPECT_EQ(h.clock_offset_ns, -250);
  EXPECT_EQ(h.clock_max_error_ns, 12'000);
  EXPECT_TRUE(h.synchronised);
  t.status("vehicle", core::Role::effect, 7, 1240, std::nullopt, kT0 + kS);
  EXPECT_FALSE(t.snapshot(kT0 + kS).has_clock);
}

TEST(NodeTracker, SnapshotsAreSafeWhileAnotherThreadWrites) {
  NodeTracker t("http://a:1", std::chrono::seconds(3));
  std::thread writer([&] {
    for (int i = 0; i < 20000; ++i) {
      t.contact(kT0 + i);
      t.stored(1, i, kT0 + i);
    }
  });
  std::uint64_t last = 0;
  for (int i = 0; i < 2000; ++i) {
    const auto h = t.snapshot(kT0 + 20000);
    EXPECT_GE(h.events, last);
    last = h.events;
  }
  writer.join();
  EXPECT_EQ(t.snapshot(kT0 + 20000).events, 20000u);
}

}  // namespace
}  // namespace m2mlat::collect
