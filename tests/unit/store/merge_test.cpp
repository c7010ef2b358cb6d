// Offline merge: two board stores joined into a campaign store hold every board event once, keep the
// nodes' sessions apart, and merging again (or a store that grew) adds only what is new.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/merge.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

namespace m2mlat::store::merge_test {
namespace {

using testing::TempDir;

core::TimePoint rt(std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); }

// A board store with one session of `count` events on "wheel", 1 s apart from `t0`.
std::int64_t record(store::Store& board, const std::string& node, core::Role role, std::int64_t t0, int count) {
  store::Session session;
  session.node = node;
  session.role = role;
  session.label = "run-1";
  session.start = rt(t0);
  const auto id = board.begin_session(session);
  std::vector<core::Event> events;
  for (int i = 0; i < count; ++i) {
    core::Event e;
    e.node = node;
    e.channel = "wheel";
    e.time = rt(t0 + i * 1'000'000'000LL);
    e.seqno = static_cast<std::uint64_t>(i + 1);
    e.line_seqno = e.seqno;
    events.push_back(e);
  }
  board.append_events(id, events);
  return id;
}

TEST(Merge, JoinsBoardsOnceAndTakesOnlyWhatIsNew) {
  TempDir dir;
  const std::int64_t t0 = 1'700'000'000'000'000'000;
  auto op = store::Store::open(dir.file("operator.db"));
  auto veh = store::Store::open(dir.file("vehicle.db"));
  record(op, "operator", core::Role::cause, t0, 30);
  const auto vehicle_session = record(veh, "vehicle", core::Role::effect, t0 + 800'000'000, 30);

  auto campaign = store::Store::open(dir.file("campaign.db"));
  // Small chunks: the merge goes through several transactions.
  const auto a = merge_store(campaign, op.path(), 7);
  const auto b = merge_store(campaign, veh.path(), 7);
  EXPECT_EQ(a.events, 30);
  EXPECT_EQ(b.events, 30);
  EXPECT_EQ(a.nodes, std::vector<std::string>{"operator"});
  EXPECT_EQ(campaign.event_count(), 60);

  // Again: nothing new.
  EXPECT_EQ(merge_store(campaign, op.path()).events, 0);
  EXPECT_EQ(merge_store(campaign, veh.path()).events, 0);
  EXPECT_EQ(campaign.event_count(), 60);

  // The vehicle board recorded more and ended its session: only that is taken, the end is learnt.
  core::Event late;
  late.node = "vehicle";
  late.channel = "wheel";
  late.time = rt(t0 + 40'000'000'000LL);
  veh.append_events(vehicle_session, std::vector{late});
  veh.end_session(vehicle_session, rt(t0 + 41'000'000'000LL));
  EXPECT_EQ(merge_store(campaign, veh.path()).events, 1);
  EXPECT_EQ(campaign.event_count(), 61);
  const auto sessions = campaign.sessions();
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_EQ(sessions[1].node, "vehicle");
  EXPECT_EQ(sessions[1].role, core::Role::effect);
  EXPECT_EQ(sessions[1].end, rt(t0 + 41'000'000'000LL));

  // Every event is in its node's session, with its timestamps and kernel counters.
  store::EventFilter vehicle;
  vehicle.node = "vehicle";
  const auto got = campaign.events_in_time(rt(0), rt(t0 * 2), vehicle);
  ASSERT_EQ(got.size(), 31u);
  EXPECT_EQ(got[0].event.time, rt(t0 + 800'000'000));
  EXPECT_EQ(got[0].event.seqno, 1u);
  EXPECT_TRUE(campaign.integrity_ok());
}

TEST(Merge, RefusesTheCampaignItselfAndNonStores) {
  TempDir dir;
  auto campaign = store::Store::open(dir.file("campaign.db"));
  EXPECT_THROW(merge_store(campaign, campaign.path()), core::Error);
  EXPECT_THROW(merge_store(campaign, dir.file("missing.db")), core::Error);
  EXPECT_EQ(campaign.event_count(), 0);
}

}  // namespace
}  // namespace m2mlat::store::merge_test
