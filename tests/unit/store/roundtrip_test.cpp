// Every field of every record survives a write, a close and a reopen unchanged.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "m2mlat/core/version.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {
constexpr auto kMin = std::numeric_limits<std::int64_t>::min();
constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
constexpr auto kU64Max = std::numeric_limits<std::uint64_t>::max();
}  // namespace

TEST(StoreRoundTrip, SessionEveryField) {
  TempDir dir;
  const auto path = dir.file("s.m2mlat");
  Session in;
  in.label = "run 12 \xC3\xA9t\xC3\xA9";  // UTF-8 survives
  in.scenario = "urban-30kmh";
  in.node = "vehicle";
  in.role = core::Role::cause;
  in.config_json = R"({"chip":"gpiochip4","line":17,"debounce_us":[0,1.5]})";
  in.start = core::TimePoint::from_ns(core::Clock::monotonic, kMin);
  in.software_version = "9.8.7";
  std::int64_t id = 0;
  {
    auto store = Store::open(path);
    id = store.begin_session(in);
    store.end_session(id, core::TimePoint::from_ns(core::Clock::monotonic, kMax));
  }
  auto store = Store::open(path);
  const auto out = store.session(id);
  ASSERT_TRUE(out.has_value());
  Session expected = in;
  expected.id = id;
  expected.end = core::TimePoint::from_ns(core::Clock::monotonic, kMax);
  EXPECT_EQ(*out, expected);
  EXPECT_EQ(store.sessions(), std::vector<Session>{expected});
  EXPECT_FALSE(store.session(id + 1).has_value());
}

TEST(StoreRoundTrip, EmptySoftwareVersionIsThisBuild) {
  TempDir dir;
  auto store = Store::open(dir.file("s.m2mlat"));
  const auto id = store.begin_session(make_session("op"));
  EXPECT_EQ(store.session(id)->software_version, core::kVersion);
  EXPECT_FALSE(store.session(id)->end.has_value());
}

TEST(StoreRoundTrip, EventsEveryFieldClockAndEdge) {
  TempDir dir;
  const auto path = dir.file("e.m2mlat");
  std::vector<core::Event> in;
  const std::vector<std::int64_t> times{
      kMin, kMin + 1, -1, 0, 1, 1'762'872'545'550'296'135, 1'762'872'545'550'296'136, kMax - 1, kMax};
  std::uint32_t flags = 0;
  for (auto clock :
       {core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime, core::Clock::simulated}) {
    for (auto edge : {core::Edge::rising, core::Edge::falling}) {
      for (const auto ns : times) {
        core::Event e;
        e.node = "vehicle";
        e.channel = in.size() % 2 ? "wheel" : "pulse";
        e.edge = edge;
        e.time = core::TimePoint::from_ns(clock, ns);
        e.seqno = in.size() * 7 + 1;
        e.line_seqno = in.size() + 1;
        e.flags = flags;
        flags = flags * 3 + 1;  // varied bit patterns
        in.push_back(e);
      }
    }
  }
  // Extremes of the unsigned and 32-bit fields.
  in.front().seqno = kU64Max;
  in.front().line_seqno = std::uint64_t{1} << 63;
  in.front().flags = std::numeric_limits<std::uint32_t>::max();
  in.back().seqno = 0;
  in.back().line_seqno = 0;
  in.back().flags = core::kFlagNoKernelSeqno | core::kFlagAfterClockStep;

  std::int64_t session = 0, first = 0;
  {
    auto store = Store::open(path);
    session = store.begin_session(make_session("vehicle"));
    first = store.append_events(session, in);
  }
  auto store = Store::open(path);
  const auto out = store.events_after(0, in.size() + 10);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i].seq, first + static_cast<std::int64_t>(i));
    EXPECT_EQ(out[i].session_id, session);
    EXPECT_EQ(out[i].event, in[i]) << "event " << i;
  }
  // A 1 ns difference at an epoch-sized timestamp (beyond a double's 2^53) is kept exactly.
  const auto& a = out[5].event.time;
  const auto& b = out[6].event.time;
  EXPECT_EQ((b - a).count(), 1);
  EXPECT_EQ(store.last_seq(), first + static_cast<std::int64_t>(in.size()) - 1);
}

TEST(StoreRoundTrip, ClockSamplesAndLosses) {
  TempDir dir;
  const auto path = dir.file("c.m2mlat");
  std::vector<ClockSample> samples;
  std::vector<Loss> losses;
  std::int64_t session = 0;
  {
    auto store = Store::open(path);
    session = store.begin_session(make_session("operator"));
    samples.push_back({session, rt(10), "chrony", kMin, kMax, -1, true, R"({"stratum":2,"ref":"GPS"})"});
    samples.push_back({session, rt(11), "adjtimex", 0, 0, 0, false, "{}"});
    samples.push_back({session, rt(12), "ptp", 1, 2, 3, true, "[1,2,3]"});
    samples.push_back({session, rt(13), "sim", -5, 7, 6, false, "null"});
    losses.push_back({session, "wheel", rt(20), kU64Max, 1, "seqno_gap"});
    losses.push_back({session, "wheel", rt(21), 5, kU64Max, "line_seqno_gap"});
    losses.push_back({session, "", rt(22), 0, 3, "kmsg_gap"});
    losses.push_back({session, "", rt(23), 9, 1, "overflow"});
    losses.push_back({session, "", core::TimePoint::from_ns(core::Clock::boottime, kMax), 1, 1, "restart"});
    store.append_clock_samples(samples);
    store.append_losses(losses);
  }
  auto store = Store::open(path);
  EXPECT_EQ(store.clock_samples(), samples);
  EXPECT_EQ(store.clock_samples(session), samples);
  EXPECT_EQ(store.losses(), losses);
  EXPECT_EQ(store.losses(session), losses);
  EXPECT_TRUE(store.clock_samples(session + 1).empty());
  EXPECT_TRUE(store.losses(session + 1).empty());
}

TEST(StoreRoundTrip, OneBatchWritesEventsLossesAndSamplesTogether) {
  TempDir dir;
  auto store = Store::open(dir.file("b.m2mlat"));
  const auto session = store.begin_session(make_session("vehicle"));
  Batch batch;
  batch.session_id = session;
  batch.events = {make_event("vehicle", "wheel", 100, 1), make_event("vehicle", "wheel", 200, 4)};
  batch.losses = {{session, "wheel", rt(200), 2, 2, "seqno_gap"}};
  batch.clock_samples = {{session, rt(150), "chrony", 12, 3000, 800, true, "{}"}};
  const auto result = store.append(batch);
  EXPECT_EQ(result, (AppendResult{1, 2}));
  EXPECT_EQ(store.event_count(), 2);
  EXPECT_EQ(store.event_count(session), 2);
  EXPECT_EQ(store.losses(), batch.losses);
  EXPECT_EQ(store.clock_samples(), batch.clock_samples);
  EXPECT_EQ(store.append(Batch{}), (AppendResult{0, 0}));  // an empty batch is no commit of events
}

TEST(StoreRoundTrip, ALargeBatchKeepsEveryEventInOrderWithConsecutiveSeqs) {
  // Large batches go in blocks of several rows per statement and the rest row by row: sizes below,
  // at and above a block, across two batches, with every field varied.
  TempDir dir;
  auto store = Store::open(dir.file("large.m2mlat"));
  const auto session = store.begin_session(make_session("vehicle"));
  std::vector<core::Event> all;
  std::int64_t expected_first = 1;
  for (const std::size_t size : {1u, 31u, 32u, 33u, 100u, 517u}) {
    Batch batch;
    batch.session_id = session;
    for (std::size_t i = 0; i < size; ++i) {
      const auto n = all.size() + 1;
      auto e =
          make_event("vehicle", n % 3 == 0 ? "steer" : "wheel", static_cast<std::int64_t>(n) * 1000 + 7, n);
      e.edge = n % 2 == 0 ? core::Edge::rising : core::Edge::falling;
      e.line_seqno = n + 5;
      e.flags = static_cast<std::uint32_t>(n % 32);
      batch.events.push_back(e);
      all.push_back(e);
    }
    const auto result = store.append(batch);
    EXPECT_EQ(result.first_seq, expected_first) << size;
    EXPECT_EQ(result.last_seq, expected_first + static_cast<std::int64_t>(size) - 1) << size;
    expected_first += static_cast<std::int64_t>(size);
  }
  const auto stored = store.events_after(0, 10'000);
  ASSERT_EQ(stored.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(stored[i].seq, static_cast<std::int64_t>(i) + 1);
    EXPECT_EQ(stored[i].event, all[i]) << i;
  }
}
