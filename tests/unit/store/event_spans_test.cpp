// Event spans (schema version 5, store/event_spans.hpp): every event read (by time, by session,
// channel, node, edge; counts; channels) gives what a plain scan of the events table gives, for
// events written in batches of mixed sessions, channels and clocks, taken by ingest (a merge), and
// stored by a version-4 store (its per-row indexes) before the migration; an open session is as
// readable as an ended one; a span row breaking the schema is reported.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/merge.hpp"
#include "m2mlat/store/schema.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

constexpr std::int64_t kSpanT0 = 1'700'000'000'000'000'000;

// The seqs a filter selects, in (t_ns, seq) order, by a plain scan of the events table: the answer
// the store's reads must give whatever indexes or spans they use.
std::vector<std::int64_t> span_test_scanned(const std::string& path, core::Clock clock, std::int64_t from, std::int64_t to,
                                  const EventFilter& filter) {
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  sqlite::Statement query(db,
                          "SELECT e.seq FROM events e NOT INDEXED JOIN sessions s ON s.id = e.session_id "
                          "WHERE e.clock = ?1 AND e.t_ns BETWEEN ?2 AND ?3 AND (?4 IS NULL OR e.session_id = ?4) "
                          "AND (?5 IS NULL OR s.node = ?5) AND (?6 IS NULL OR e.channel = ?6) "
                          "AND (?7 IS NULL OR e.edge = ?7) ORDER BY e.t_ns, e.seq");
  query.bind(1, static_cast<std::int64_t>(clock));
  query.bind(2, from);
  query.bind(3, to);
  if (filter.session_id) query.bind(4, *filter.session_id);
  else query.bind_null(4);
  if (filter.node) query.bind(5, *filter.node);
  else query.bind_null(5);
  if (filter.channel) query.bind(6, *filter.channel);
  else query.bind_null(6);
  if (filter.edge) query.bind(7, static_cast<std::int64_t>(*filter.edge));
  else query.bind_null(7);
  std::vector<std::int64_t> out;
  while (query.step()) out.push_back(query.column_int64(0));
  return out;
}

std::int64_t span_test_scanned_count(const std::string& path, std::optional<std::int64_t> session) {
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  sqlite::Statement query(db, "SELECT count(*) FROM events NOT INDEXED WHERE ?1 IS NULL OR session_id = ?1");
  if (session) query.bind(1, *session);
  else query.bind_null(1);
  query.step();
  return query.column_int64(0);
}

// Every read of `store` against the plain scan, for several windows and filters.
void expect_reads_match_a_scan(const Store& store) {
  const std::string& path = store.path();
  std::vector<EventFilter> filters(1);
  for (const auto& session : store.sessions()) {
    EventFilter f;
    f.session_id = session.id;
    filters.push_back(f);
    for (const auto& channel : store.channels(session.id)) {
      f.channel = channel;
      filters.push_back(f);
      f.edge = core::Edge::rising;
      filters.push_back(f);
      f.edge.reset();
    }
    EXPECT_EQ(store.event_count(session.id), span_test_scanned_count(path, session.id)) << "session " << session.id;
  }
  EventFilter by_node;
  by_node.node = "vehicle";
  filters.push_back(by_node);
  by_node.channel = "wheel";
  filters.push_back(by_node);
  EXPECT_EQ(store.event_count(), span_test_scanned_count(path, std::nullopt));
  constexpr auto kMin = std::numeric_limits<std::int64_t>::min(), kMax = std::numeric_limits<std::int64_t>::max();
  const std::vector<std::pair<std::int64_t, std::int64_t>> windows{
      {kMin, kMax}, {kSpanT0 + 1'000'000, kSpanT0 + 3'500'000}, {kSpanT0 + 2'000'000, kSpanT0 + 2'000'000}, {kSpanT0 - 10, kSpanT0 - 1}};
  for (const auto clock : {core::Clock::realtime, core::Clock::monotonic})
    for (const auto& [from, to] : windows)
      for (const auto& filter : filters) {
        const auto want = span_test_scanned(path, clock, from, to, filter);
        const auto f = core::TimePoint::from_ns(clock, from), t = core::TimePoint::from_ns(clock, to);
        std::vector<std::int64_t> got;
        for (const auto& e : store.events_in_time(f, t, filter)) got.push_back(e.seq);
        const std::string what = "clock " + std::string(core::to_string(clock)) + " window " + std::to_string(from) +
                                 ".." + std::to_string(to) + " session " +
                                 std::to_string(filter.session_id.value_or(0)) + " channel " +
                                 filter.channel.value_or("*") + " node " + filter.node.value_or("*");
        EXPECT_EQ(got, want) << "events_in_time, " << what;
        EXPECT_EQ(store.timestamps(f, t, filter).seq, want) << "timestamps, " << what;
      }
}

// Batches as a recorder and an import write them: two sessions of two nodes, two channels, stamps
// out of order within a batch, a few events on the monotonic clock, batches of 1 to 700 events.
void fill_mixed_batches(Store& store) {
  const auto vehicle = store.begin_session(make_session("vehicle", "a"));
  const auto op = store.begin_session(make_session("operator", "b"));
  std::int64_t k = 0;
  for (const std::size_t size : {1u, 700u, 33u, 2u, 512u}) {
    for (const auto session : {vehicle, op}) {
      std::vector<core::Event> batch;
      for (std::size_t i = 0; i < size; ++i, ++k) {
        const std::string node = session == vehicle ? "vehicle" : "operator";
        auto e = make_event(node, k % 3 == 0 ? "motion" : "wheel", kSpanT0 + (k * 2'000) % 5'000'000 + (k % 7) * 100,
                            static_cast<std::uint64_t>(k));
        e.edge = k % 2 == 0 ? core::Edge::rising : core::Edge::falling;
        if (k % 50 == 0) e.time = core::TimePoint::from_ns(core::Clock::monotonic, 1'000'000 + k);
        batch.push_back(e);
      }
      store.append_events(session, batch);
    }
  }
  store.end_session(op, rt(kSpanT0 + 10'000'000));  // the vehicle's stays open, as a recorder's killed one
}

}  // namespace

TEST(EventSpans, ReadsOfMixedBatchesMatchAPlainScan) {
  TempDir dir;
  auto store = Store::open(dir.file("mixed.m2mlat"));
  fill_mixed_batches(store);
  ASSERT_EQ(store.event_count(), 2 * (1 + 700 + 33 + 2 + 512));
  EXPECT_EQ(store.channels(1), (std::vector<std::string>{"motion", "wheel"}));
  expect_reads_match_a_scan(store);
  store.check_rows();
  EXPECT_TRUE(store.integrity_ok());
}

TEST(EventSpans, EventsTakenByAMergeReadAsTheBoardsDo) {
  TempDir dir;
  {
    auto board = Store::open(dir.file("board.m2mlat"));
    fill_mixed_batches(board);
  }
  auto campaign = Store::open(dir.file("campaign.m2mlat"));
  const auto other = campaign.begin_session(make_session("vehicle", "local"));
  campaign.append_events(other, std::vector{make_event("vehicle", "wheel", kSpanT0 + 2'000'000, 1)});
  merge_store(campaign, dir.file("board.m2mlat"), 300);  // chunks of 300: a span per chunk and group
  EXPECT_EQ(campaign.event_count(), 1 + 2 * (1 + 700 + 33 + 2 + 512));
  expect_reads_match_a_scan(campaign);
}

// A version-4 store (per-row indexes, no spans) with events of two sessions interleaved and more than
// 4096 seqs: the migration gives them spans and drops the indexes, and every read is the same.
TEST(EventSpans, AVersion4StoreIsMigratedAndReadsTheSame) {
  TempDir dir;
  const auto path = dir.file("v4.m2mlat");
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
    const auto all = schema::migrations();
    ASSERT_GE(all.size(), 5u);
    ASSERT_EQ(schema::migrate(db, all.first(4)), 4);
    db.exec(
        "INSERT INTO sessions (label, scenario, node, role, config_json, start_clock, start_ns, "
        "software_version) VALUES ('a', 'bench', 'vehicle', 2, '{}', 0, 5, 'm2mlat 0.old'), "
        "('b', 'bench', 'operator', 1, '{}', 0, 5, 'm2mlat 0.old')");
    // 9000 events: session 1 and 2 alternating in runs of 3, channels by seq, some on monotonic.
    db.exec(
        "WITH RECURSIVE k(n) AS (SELECT 1 UNION ALL SELECT n + 1 FROM k WHERE n < 9000) "
        "INSERT INTO events (seq, session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
        "SELECT n, 1 + (n / 3) % 2, CASE WHEN n % 5 = 0 THEN 'motion' ELSE 'wheel' END, n % 2, "
        "CASE WHEN n % 97 = 0 THEN 1 ELSE 0 END, 1700000000000000000 + (n * 7919) % 6000000, n, n, 0 FROM k");
    db.exec("UPDATE sessions SET end_clock = 0, end_ns = 1700000000010000000 WHERE id = 2");
  }
  std::vector<std::int64_t> before;
  for (const std::int64_t session : {1, 2}) {
    EventFilter f;
    f.session_id = session;
    const auto all = span_test_scanned(path, core::Clock::realtime, std::numeric_limits<std::int64_t>::min(),
                             std::numeric_limits<std::int64_t>::max(), f);
    before.insert(before.end(), all.begin(), all.end());
  }
  ASSERT_EQ(before.size(), 9000u - 9000u / 97);
  auto store = Store::open(path);
  EXPECT_EQ(store.schema_version(), schema::latest_version());
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
    EXPECT_EQ(db.query_int("SELECT count(*) FROM sqlite_schema WHERE name LIKE 'events_by_%'"), 0);
    EXPECT_EQ(db.query_int("SELECT sum(count) FROM event_spans"), 9000);
    EXPECT_GE(db.query_int("SELECT count(*) FROM event_spans"), 3 * 2 * 2);  // buckets x sessions x channels
  }
  EXPECT_EQ(store.event_count(), 9000);
  expect_reads_match_a_scan(store);
  // It takes new events as a new store does.
  store.append_events(1, std::vector{make_event("vehicle", "wheel", kSpanT0 + 4'000'000, 1)});
  expect_reads_match_a_scan(store);
  store.check_rows();
}

TEST(EventSpans, ASpanRowBreakingTheSchemaIsReported) {
  TempDir dir;
  const auto path = dir.file("damaged.m2mlat");
  {
    auto store = Store::open(path);
    fill_mixed_batches(store);
  }
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    db.exec("PRAGMA ignore_check_constraints = ON");
    db.exec("UPDATE event_spans SET last_ns = first_ns - 1 WHERE id = 3");
  }
  auto store = Store::open(path);
  try {
    store.check_rows();
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("table 'event_spans' row id 3: field 'last_ns'"), std::string::npos)
        << e.what();
  }
}
