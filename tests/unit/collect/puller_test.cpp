// The puller against the in-process agent twin and a real campaign store: catch-up by pages,
// following the stream, new sessions, clock samples and losses, and every item stored exactly once
// through dropped connections, garbage, a frozen agent and a restart of the puller.
#include "m2mlat/collect/puller.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>

#include "agent_twin.hpp"
#include "m2mlat/collect/coordinator.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::collect {
namespace {

using testing::AgentTwin;
using testing::Fault;
using testing::TempDir;

// What identifies an origin event in the campaign: node, time, channel, seqno.
using Key = std::tuple<std::string, std::int64_t, std::string, std::uint64_t>;
Key key(const store::StoredEvent& e) {
  return {e.event.node, e.event.time.ns(), e.event.channel, e.event.seqno};
}

std::string make_campaign(const TempDir& dir) {
  const auto path = dir.file("campaign.db");
  store::Store::open(path);
  return path;
}

PullerOptions options_for(const AgentTwin& twin, const std::string& campaign) {
  PullerOptions o;
  o.url = twin.url();
  o.store_path = campaign;
  o.client.connect_timeout = std::chrono::milliseconds(300);
  // A safety net only (the frozen-agent test sets its own): a page of 10,000 events from the twin took
  // more than 3 s under the sanitizers on a loaded machine, and the catch-up failed on it.
  o.client.read_timeout = std::chrono::seconds(30);
  o.backoff_min = std::chrono::milliseconds(20);
  o.backoff_max = std::chrono::milliseconds(200);
  o.side_interval = std::chrono::milliseconds(100);
  return o;
}

// The campaign's events, checked to hold each of the twin's events exactly once.
void expect_exactly_once(const std::string& campaign, const std::vector<AgentTwin*>& twins) {
  auto store = store::Store::open(campaign, {store::Durability::normal, true});
  std::map<Key, int> seen;
  for (const auto& e : store.events_after(0, 100'000'000)) ++seen[key(e)];
  std::size_t expected = 0;
  for (auto* twin : twins) {
    for (const auto& e : twin->events()) {
      const auto it = seen.find(key(e));
      ASSERT_NE(it, seen.end()) << "missing " << e.event.node << " seq " << e.seq;
      EXPECT_EQ(it->second, 1) << e.event.node << " seq " << e.seq;
      ++expected;
    }
  }
  EXPECT_EQ(seen.size(), expected);
  EXPECT_TRUE(store.integrity_ok());
}

// Waits until `done` holds (up to 10 s).
template <class F>
bool eventually(F done) {
  for (int i = 0; i < 1000; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

std::int64_t stored_of(const std::string& campaign, const std::string& origin) {
  return store::Store::open(campaign, {store::Durability::normal, true}).ingest_cursor(origin).events;
}

struct Errors {
  std::mutex mutex;
  std::vector<std::string> lines;
  ErrorSink sink() {
    return [this](const std::string&, const std::string& message) {
      std::lock_guard lock(mutex);
      lines.push_back(message);
    };
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return lines.size();
  }
};

TEST(Puller, CatchesUpByPagesAndTakesNothingTwice) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  for (int i = 0; i < 25; ++i) twin.append(1000);
  twin.append_clock_sample(300);
  twin.append_loss(10, 3);
  const auto campaign = make_campaign(dir);
  auto tracker = std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3));
  Puller puller(options_for(twin, campaign), tracker, nullptr);
  puller.catch_up_once();
  EXPECT_EQ(twin.requests("/v1/events"), 3);  // 10000 + 10000 + 5000
  expect_exactly_once(campaign, {&twin});
  puller.catch_up_once();  // again: nothing new
  expect_exactly_once(campaign, {&twin});

  auto store = store::Store::open(campaign, {store::Durability::normal, true});
  const auto cursor = store.ingest_cursor(twin.store_id());
  EXPECT_EQ(cursor.events, 25000);
  EXPECT_EQ(cursor.clock_samples, 1);
  EXPECT_EQ(cursor.losses, 1);
  ASSERT_EQ(store.clock_samples().size(), 1u);
  EXPECT_EQ(store.clock_samples()[0].offset_ns, 300);
  ASSERT_EQ(store.losses().size(), 1u);
  EXPECT_EQ(store.losses()[0].count, 3u);
  const auto sessions = store.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].node, "vehicle");
  EXPECT_EQ(sessions[0].label, "twin");

  const auto h = tracker->snapshot(core::now_ns(CLOCK_REALTIME));
  EXPECT_EQ(h.state, NodeState::ok);
  EXPECT_EQ(h.events, 25000u);
  EXPECT_EQ(h.cursor_seq, 25000);
  EXPECT_EQ(h.lost, 3u);
  EXPECT_TRUE(h.has_clock);
}

TEST(Puller, FollowsTheStreamAndNewSessions) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  twin.append(100);
  const auto campaign = make_campaign(dir);
  auto tracker = std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3));
  Errors errors;
  Puller puller(options_for(twin, campaign), tracker, errors.sink());
  puller.start();
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 100; }));
  for (int i = 0; i < 20; ++i) {
    twin.append(7);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  twin.new_session("second");  // an event of a session the puller has not seen
  twin.append(30);
  twin.append_clock_sample(-40);
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 270; }));
  ASSERT_TRUE(eventually([&] {
    return store::Store::open(campaign, {store::Durability::normal, true})
               .ingest_cursor(twin.store_id())
               .clock_samples == 1;
  }));
  puller.stop(true);
  expect_exactly_once(campaign, {&twin});
  auto store = store::Store::open(campaign, {store::Durability::normal, true});
  const auto sessions = store.sessions();
  ASSERT_EQ(sessions.size(), 2u);
  EXPECT_TRUE(sessions[0].end.has_value());  // the first one's end came with the re-read
  EXPECT_EQ(sessions[1].label, "second");
  EXPECT_EQ(store.event_count(sessions[1].id), 30);
  EXPECT_EQ(errors.count(), 0u);
  EXPECT_GT(tracker->snapshot(core::now_ns(CLOCK_REALTIME)).events_per_s, 0.0);
}

TEST(Puller, PollsInsteadOfStreamingWhenAsked) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  const auto campaign = make_campaign(dir);
  auto o = options_for(twin, campaign);
  o.poll_interval = std::chrono::milliseconds(50);
  Puller puller(o, std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)), nullptr);
  puller.start();
  for (int i = 0; i < 10; ++i) twin.append(11);
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 110; }));
  puller.stop(false);
  EXPECT_EQ(twin.requests("/v1/events/stream"), 0);
  expect_exactly_once(campaign, {&twin});
}

TEST(Puller, SurvivesDroppedConnectionsGarbageAndAFrozenAgentExactlyOnce) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  for (int i = 0; i < 3; ++i) twin.append(5000);
  const auto campaign = make_campaign(dir);
  auto tracker = std::make_shared<NodeTracker>(twin.url(), std::chrono::milliseconds(300));
  Errors errors;
  auto o = options_for(twin, campaign);
  o.page = 4000;
  o.client.read_timeout = std::chrono::milliseconds(800);
  Puller puller(o, tracker, errors.sink());
  twin.set_fault(Fault::drop, 3);
  puller.start();
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 15000; }));
  EXPECT_GE(errors.count(), 3u);

  twin.set_fault(Fault::garbage, 2);
  twin.append(123);  // the stream brings these; garbage hits the next catch-up
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 15123; }));

  // Frozen for longer than the read timeout: unreachable (or at least stale), then back.
  twin.set_fault(Fault::freeze);
  ASSERT_TRUE(eventually([&] { return tracker->snapshot(core::now_ns(CLOCK_REALTIME)).state != NodeState::ok; }));
  ASSERT_TRUE(
      eventually([&] { return tracker->snapshot(core::now_ns(CLOCK_REALTIME)).state == NodeState::unreachable; }));
  EXPECT_NE(tracker->snapshot(core::now_ns(CLOCK_REALTIME)).last_error.find("/v1/"), std::string::npos);
  twin.append(77);
  twin.set_fault(Fault::none);
  ASSERT_TRUE(eventually([&] { return stored_of(campaign, twin.store_id()) == 15200; }));
  ASSERT_TRUE(eventually([&] { return tracker->snapshot(core::now_ns(CLOCK_REALTIME)).state == NodeState::ok; }));
  puller.stop(false);
  expect_exactly_once(campaign, {&twin});
}

TEST(Puller, ANewPullerResumesFromTheStoresCursor) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  twin.append(2500);
  const auto campaign = make_campaign(dir);
  {
    auto o = options_for(twin, campaign);
    o.page = 1000;
    Puller first(o, std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)), nullptr);
    first.catch_up_once();
  }
  twin.append(500);
  const int before = twin.requests("/v1/events");
  Puller second(options_for(twin, campaign),
                std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)), nullptr);
  second.catch_up_once();
  EXPECT_EQ(twin.requests("/v1/events") - before, 1);  // only the 500 new ones, in one page
  expect_exactly_once(campaign, {&twin});
}

// A gyroscope's raw samples: more blocks than a page holds, over two sessions, taken exactly once
// by a first puller and the rest (with new ones) by a second that resumes from the store's cursor.
TEST(Puller, TakesRateBlocksByPagesExactlyOnceAcrossPullers) {
  TempDir dir;
  AgentTwin twin(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  twin.append(10);
  for (std::uint64_t i = 0; i < 20; ++i) twin.append_rate_block(i * 100, 100);
  const auto campaign = make_campaign(dir);
  {
    Puller first(options_for(twin, campaign), std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)),
                 nullptr);
    first.catch_up_once();
  }
  EXPECT_EQ(twin.requests("/v1/rate-blocks"), 2);  // 16 + 4
  twin.new_session("second");
  for (std::uint64_t i = 20; i < 23; ++i) twin.append_rate_block(i * 100, 100);
  Puller second(options_for(twin, campaign), std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)),
                nullptr);
  second.catch_up_once();
  second.catch_up_once();  // nothing new: nothing stored twice

  const auto store = store::Store::open(campaign, {store::Durability::normal, false});
  const auto channels = store.rate_channels();
  ASSERT_EQ(channels.size(), 2u);
  EXPECT_EQ(channels[0].samples, 2000);
  EXPECT_EQ(channels[1].samples, 300);
  const auto first_trace = store.rate_trace(channels[0].session_id, "gyro");
  for (std::size_t i = 0; i < first_trace.samples.size(); ++i)
    ASSERT_EQ(first_trace.samples[i].time_ns, 1'700'000'000'000'000'000 + static_cast<std::int64_t>(i) * 125'000);
  EXPECT_EQ(store.ingest_cursor(twin.store_id()).rate_blocks, 23);
}

// Software markers over two sessions: taken exactly once, each in the campaign's copy of its session,
// by a first puller and (with new ones) a second that resumes from the store's cursor.
TEST(Puller, TakesMarkersExactlyOnceAcrossPullers) {
  TempDir dir;
  AgentTwin twin(dir.file("operator.db"), "operator", core::Role::cause);
  for (int i = 1; i <= 3; ++i) twin.append_marker(std::to_string(i));
  const auto campaign = make_campaign(dir);
  {
    Puller first(options_for(twin, campaign), std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)),
                 nullptr);
    first.catch_up_once();
  }
  twin.new_session("second");
  twin.append_marker("4");
  Puller second(options_for(twin, campaign), std::make_shared<NodeTracker>(twin.url(), std::chrono::seconds(3)),
                nullptr);
  second.catch_up_once();
  second.catch_up_once();
  const auto store = store::Store::open(campaign, {store::Durability::normal, false});
  const auto markers = store.markers();
  ASSERT_EQ(markers.size(), 4u);
  const auto sessions = store.sessions();
  ASSERT_EQ(sessions.size(), 2u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(markers[i].marker.key, std::to_string(i + 1));
    EXPECT_EQ(markers[i].marker.session_id, sessions[i < 3 ? 0 : 1].id);
  }
  EXPECT_EQ(store.ingest_cursor(twin.store_id()).markers, 4);
}

TEST(Coordinator, PullsTwoAgentsStartsAndStopsTheirSessions) {
  TempDir dir;
  AgentTwin op(dir.file("operator.db"), "operator", core::Role::cause);
  AgentTwin veh(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  op.append(40);
  veh.append(60);
  CoordinatorOptions o;
  o.agents = {op.url(), veh.url() + "/"};
  o.store_path = dir.file("campaign.db");
  o.client.read_timeout = std::chrono::seconds(30);  // a safety net, as in options_for
  o.start_session = NewSession{"run-1", "bench"};
  o.stop_session = true;
  Errors errors;
  Coordinator coordinator(o, errors.sink());
  const auto begun = coordinator.start();
  ASSERT_EQ(begun.size(), 2u);
  EXPECT_EQ(begun[0].node, "operator");
  EXPECT_EQ(begun[1].label, "run-1");
  op.append(5);
  veh.append(6);
  ASSERT_TRUE(eventually([&] {
    return stored_of(o.store_path, op.store_id()) == 45 && stored_of(o.store_path, veh.store_id()) == 66;
  }));
  const auto health = coordinator.health();
  ASSERT_EQ(health.size(), 2u);
  EXPECT_EQ(health[0].node, "operator");
  EXPECT_EQ(health[0].role, core::Role::cause);
  EXPECT_EQ(health[1].node, "vehicle");
  for (const auto& h : health) EXPECT_EQ(h.state, NodeState::ok) << h.url << " " << h.last_error;
  coordinator.stop();
  expect_exactly_once(o.store_path, {&op, &veh});
  auto store = store::Store::open(o.store_path, {store::Durability::normal, true});
  int ended_runs = 0;
  for (const auto& s : store.sessions()) ended_runs += s.label == "run-1" && s.end.has_value();
  EXPECT_EQ(ended_runs, 2);  // both agents' sessions stopped, and their ends taken
  EXPECT_EQ(errors.count(), 0u);
}

TEST(Coordinator, AnAgentWhoseSessionIsNotTheRunsRejoinsIt) {
  TempDir dir;
  AgentTwin op(dir.file("operator.db"), "operator", core::Role::cause);
  AgentTwin veh(dir.file("vehicle.db"), "vehicle", core::Role::effect);
  CoordinatorOptions o;
  o.agents = {op.url(), veh.url()};
  o.store_path = dir.file("campaign.db");
  o.client.read_timeout = std::chrono::seconds(30);
  o.start_session = NewSession{"run-1", "bench"};
  Errors errors;
  Coordinator coordinator(o, errors.sink());
  ASSERT_EQ(coordinator.start().size(), 2u);
  const auto run_session = veh.session();
  veh.append(3);  // (the twin's clock moves with its events)
  veh.new_session("", "unnamed");  // the vehicle's agent restarted with a session of its own
  veh.append(3);
  const auto own = veh.session();
  // Within a side poll (1 s) the puller begins the run's session on it again, and says so.
  ASSERT_TRUE(eventually([&] { return veh.session() != own; }));
  coordinator.stop();
  const auto store = store::Store::open(dir.file("vehicle.db"), {store::Durability::normal, false});
  const auto now = store.session(veh.session());
  ASSERT_TRUE(now);
  EXPECT_EQ(now->label, "run-1");
  EXPECT_EQ(now->scenario, "bench");
  EXPECT_NE(veh.session(), run_session);
  ASSERT_EQ(errors.count(), 1u);
  EXPECT_NE(errors.lines[0].find("is not the run's: rejoined the run as session"), std::string::npos) << errors.lines[0];
}

TEST(Coordinator, RefusesNoAgentsAndTheSameAgentTwice) {
  CoordinatorOptions o;
  o.store_path = "x.db";
  EXPECT_THROW(Coordinator(o, nullptr), core::Error);
  o.agents = {"http://127.0.0.1:9/", "http://127.0.0.1:9"};
  EXPECT_THROW(Coordinator(o, nullptr), core::Error);
}

}  // namespace
}  // namespace m2mlat::collect
