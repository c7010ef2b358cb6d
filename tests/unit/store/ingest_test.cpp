// Campaign stores: ingest() takes every origin item exactly once, however often and in whatever
// overlapping pieces it is given, maps origin sessions to local ones, and refuses bad batches whole.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

namespace m2mlat::store {
namespace {

using test::make_event;
using test::make_session;
using test::rt;
using test::TempDir;

// An origin store with two sessions, events, a clock sample and a loss; returns everything in it
// as one batch.
IngestBatch fill_origin(Store& origin, const std::string& node) {
  const auto a = origin.begin_session(make_session(node, "a"));
  Batch batch;
  batch.session_id = a;
  for (int i = 0; i < 5; ++i) batch.events.push_back(make_event(node, "wheel", 1'700'000'000'100'000'000 + i, i));
  batch.clock_samples.push_back({a, rt(1'700'000'000'100'000'000), "chrony", 1000, 50000, 2000, true, "{}"});
  batch.losses.push_back({a, "wheel", rt(1'700'000'000'200'000'000), 7, 2, "seqno_gap"});
  origin.append(batch);
  origin.end_session(a, rt(1'700'000'001'000'000'000));
  const auto b = origin.begin_session(make_session(node, "b"));
  origin.append_events(b, std::vector{make_event(node, "wheel", 1'700'000'002'000'000'000, 9)});

  IngestBatch out;
  out.origin = origin.store_id();
  out.sessions = origin.sessions();
  out.events = origin.events_after(0, 100);
  out.clock_samples = origin.clock_samples_after(0, 100);
  out.losses = origin.losses_after(0, 100);
  return out;
}

TEST(Ingest, EveryStoreHasItsOwnIdentity) {
  TempDir dir;
  auto a = Store::open(dir.file("a.db"));
  auto b = Store::open(dir.file("b.db"));
  EXPECT_EQ(a.store_id().size(), 32u);
  EXPECT_NE(a.store_id(), b.store_id());
  const std::string id = a.store_id();
  a = Store::open(dir.file("b.db"));
  EXPECT_EQ(Store::open(dir.file("a.db")).store_id(), id);  // kept across reopening
}

TEST(Ingest, TakesEverythingOnceAndMapsSessions) {
  TempDir dir;
  auto origin = Store::open(dir.file("vehicle.db"));
  const IngestBatch batch = fill_origin(origin, "vehicle");
  auto campaign = Store::open(dir.file("campaign.db"));
  campaign.begin_session(make_session("somebody-else"));  // local ids differ from the origin's

  const IngestCursor cursor = campaign.ingest(batch);
  EXPECT_EQ(cursor, (IngestCursor{6, 1, 1, 0, 0}));
  EXPECT_EQ(campaign.ingest_cursor(batch.origin), cursor);
  EXPECT_EQ(campaign.origins(), std::vector{batch.origin});

  // Again, and a piece that overlaps: nothing changes.
  EXPECT_EQ(campaign.ingest(batch), cursor);
  IngestBatch tail = batch;
  tail.events.erase(tail.events.begin(), tail.events.begin() + 3);
  EXPECT_EQ(campaign.ingest(tail), cursor);
  EXPECT_EQ(campaign.event_count(), 6);

  const auto sessions = campaign.sessions();
  ASSERT_EQ(sessions.size(), 3u);
  EXPECT_EQ(sessions[1].label, "a");
  EXPECT_EQ(sessions[1].node, "vehicle");
  EXPECT_TRUE(sessions[1].end.has_value());
  EXPECT_FALSE(sessions[2].end.has_value());
  const auto events = campaign.events_after(0, 100);
  ASSERT_EQ(events.size(), 6u);
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].event, batch.events[i].event);
    EXPECT_EQ(events[i].session_id, i < 5 ? sessions[1].id : sessions[2].id);
  }
  ASSERT_EQ(campaign.clock_samples().size(), 1u);
  EXPECT_EQ(campaign.clock_samples()[0].session_id, sessions[1].id);
  EXPECT_EQ(campaign.losses()[0].first_missing, 7u);
  EXPECT_TRUE(campaign.integrity_ok());
}

TEST(Ingest, ResumesAfterTheCursorAndLearnsSessionEnds) {
  TempDir dir;
  auto origin = Store::open(dir.file("operator.db"));
  auto campaign = Store::open(dir.file("campaign.db"));
  const auto s = origin.begin_session(make_session("operator"));
  origin.append_events(s, std::vector{make_event("operator", "wheel", 1'700'000'000'100'000'000, 0)});

  IngestBatch first{origin.store_id(), origin.sessions(), origin.events_after(0, 10), {}, {}, {}, {}};
  EXPECT_EQ(campaign.ingest(first).events, 1);
  origin.append_events(s, std::vector{make_event("operator", "wheel", 1'700'000'000'200'000'000, 1)});
  origin.end_session(s, rt(1'700'000'000'300'000'000));
  // The second pull carries only what is after the cursor, and the session's new end.
  const auto from = campaign.ingest_cursor(origin.store_id()).events;
  IngestBatch second{origin.store_id(), origin.sessions(), origin.events_after(from, 10), {}, {}, {}, {}};
  EXPECT_EQ(campaign.ingest(second).events, 2);
  EXPECT_EQ(campaign.event_count(), 2);
  EXPECT_EQ(campaign.sessions().at(0).end, rt(1'700'000'000'300'000'000));
}

// A session may end with its configuration completed (`m2mlat led`: its writes' largest bound);
// the campaign store learns that configuration with the end; a bad one is refused and changes nothing.
TEST(Ingest, LearnsTheConfigurationASessionEndedWith) {
  TempDir dir;
  auto origin = Store::open(dir.file("vehicle.db"));
  auto campaign = Store::open(dir.file("campaign.db"));
  auto info = make_session("vehicle");
  info.config_json = R"({"source":"led"})";
  const auto s = origin.begin_session(info);
  origin.append_events(s, std::vector{make_event("vehicle", "led", 1'700'000'000'100'000'000, 0)});
  IngestBatch first{origin.store_id(), origin.sessions(), origin.events_after(0, 10), {}, {}, {}, {}};
  campaign.ingest(first);
  EXPECT_EQ(campaign.sessions().at(0).config_json, R"({"source":"led"})");

  EXPECT_THROW(origin.end_session(s, rt(1'700'000'000'300'000'000), std::string("{not json")), core::Error);
  EXPECT_FALSE(origin.session(s)->end);
  origin.end_session(s, rt(1'700'000'000'300'000'000),
                     std::string(R"({"led_bound_ns":1500,"source":"led"})"));
  EXPECT_EQ(origin.session(s)->config_json, R"({"led_bound_ns":1500,"source":"led"})");
  IngestBatch second{origin.store_id(), origin.sessions(), {}, {}, {}, {}, {}};
  campaign.ingest(second);
  const auto local = campaign.sessions().at(0);
  EXPECT_EQ(local.end, rt(1'700'000'000'300'000'000));
  EXPECT_EQ(local.config_json, R"({"led_bound_ns":1500,"source":"led"})");
}

TEST(Ingest, RefusesBadBatchesWhole) {
  TempDir dir;
  auto origin = Store::open(dir.file("vehicle.db"));
  const IngestBatch good = fill_origin(origin, "vehicle");
  auto campaign = Store::open(dir.file("campaign.db"));

  const auto refused = [&](IngestBatch batch, const std::string& needle) {
    try {
      campaign.ingest(batch);
      ADD_FAILURE() << "accepted a batch that should fail with: " << needle;
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
    EXPECT_EQ(campaign.event_count(), 0);
    EXPECT_TRUE(campaign.sessions().empty());
    EXPECT_EQ(campaign.ingest_cursor(batch.origin), IngestCursor{});
  };
  IngestBatch batch = good;
  batch.origin.clear();
  refused(batch, "origin");
  batch = good;
  batch.origin = campaign.store_id();
  refused(batch, "this store itself");
  batch = good;
  batch.sessions.pop_back();  // the last event's session is missing
  refused(batch, "names origin session");
  batch = good;
  std::swap(batch.events[1], batch.events[2]);
  refused(batch, "order");
  batch = good;
  batch.events[2].event.node = "operator";
  refused(batch, "field 'node'");
  batch = good;
  batch.events[0].event.channel.clear();
  refused(batch, "channel");
  EXPECT_TRUE(campaign.integrity_ok());
}

}  // namespace
}  // namespace m2mlat::store
