// Store files damaged or edited by another tool: a missing table or column is a data error naming
// the file and what is missing (not a failure of the first statement that needs it), and a row
// that breaks the schema's rules (CHECK clauses switched off, a dangling session) is refused,
// naming table, row and field, instead of being left out of a read without a word.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <limits>
#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {


// A store of one closed session with five events (seq 1..5).
std::string make_store(const TempDir& dir, const std::string& name) {
  const auto path = dir.file(name);
  auto store = Store::open(path);
  const auto id = store.begin_session(make_session("vehicle"));
  std::vector<core::Event> events;
  for (int i = 1; i <= 5; ++i)
    events.push_back(make_event("vehicle", "wheel", 1'700'000'000'000'000'000 + i));
  store.append_events(id, events);
  store.end_session(id, rt(1'700'000'000'000'000'100));
  return path;
}

core::Error open_failure(const std::string& path, bool read_only) {
  try {
    Options options;
    options.read_only = read_only;
    Store::open(path, options);
  } catch (const core::Error& e) {
    return e;
  }
  return core::Error(core::ErrorKind::internal, "no error");
}

core::Error read_failure(const Store& store) {
  try {
    store.timestamps(
        core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::min()),
        core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max()));
  } catch (const core::Error& e) {
    return e;
  }
  return core::Error(core::ErrorKind::internal, "no error");
}

}  // namespace

TEST(DamagedStore, AMissingTableOrColumnIsADataErrorNamingIt) {
  TempDir dir;
  const auto no_events = make_store(dir, "no-events.db");
  edit(no_events, "DROP TABLE events");
  for (const bool read_only : {true, false}) {
    const auto e = open_failure(no_events, read_only);
    EXPECT_EQ(e.kind(), core::ErrorKind::data) << e.what();
    EXPECT_TRUE(contains(e.what(), no_events)) << e.what();
    EXPECT_TRUE(contains(e.what(), "table 'events' is missing")) << e.what();
  }
  const auto no_column = make_store(dir, "no-column.db");
  edit(no_column, "ALTER TABLE losses DROP COLUMN kind");
  const auto e = open_failure(no_column, true);
  EXPECT_EQ(e.kind(), core::ErrorKind::data) << e.what();
  EXPECT_TRUE(contains(e.what(), "table 'losses' has no column 'kind'")) << e.what();
}

TEST(DamagedStore, RowsBreakingTheSchemaAreRefusedNotLeftOut) {
  TempDir dir;
  struct Case {
    std::string sql, message;
  };
  const Case cases[] = {
      {"UPDATE events SET edge = 2 WHERE seq = 3", "table 'events' row seq 3: field 'edge' holds 2"},
      {"UPDATE events SET clock = 9 WHERE seq = 4", "table 'events' row seq 4: field 'clock' holds 9"},
      {"UPDATE events SET channel = '' WHERE seq = 2", "table 'events' row seq 2: field 'channel' holds ''"},
      {"UPDATE events SET session_id = 77 WHERE seq = 5",
       "table 'events' row seq 5: field 'session_id' holds 77"},
      {"UPDATE events SET flags = -1 WHERE seq = 1", "table 'events' row seq 1: field 'flags' holds -1"},
      {"UPDATE events SET t_ns = 'soon' WHERE seq = 1",
       "table 'events' row seq 1: field 't_ns' holds 'soon'"},
      {"UPDATE sessions SET role = 7", "table 'sessions' row id 1: field 'role' holds 7"},
      {"INSERT INTO losses (session_id, channel, clock, t_ns, first_missing, count, kind) "
       "VALUES (1, 'wheel', 0, 5, 1, 0, 'seqno_gap')",
       "table 'losses' row id 1: field 'count' holds 0"},
      // Events outside their spans: read through the spans, they would be left out without a word.
      {"INSERT INTO events (session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
       "VALUES (1, 'wheel', 1, 0, 9, 9, 9, 0)",
       "table 'events' holds 6 rows, its spans (table 'event_spans') count 5"},
      {"DELETE FROM events WHERE seq = 2", "table 'events' holds 4 rows, its spans (table 'event_spans') count 5"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const auto path = make_store(dir, "case" + std::to_string(n++) + ".db");
    edit(path, c.sql);
    Options read_only;
    read_only.read_only = true;
    const auto store = Store::open(path, read_only);
    const auto e = read_failure(store);
    EXPECT_EQ(e.kind(), core::ErrorKind::data) << c.sql << ": " << e.what();
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
    EXPECT_TRUE(contains(e.what(), c.message)) << c.sql << ": " << e.what();
  }
  // An untouched store reads as before.
  const auto good = make_store(dir, "good.db");
  const auto store = Store::open(good);
  EXPECT_NO_THROW(store.check_rows());
  EXPECT_EQ(store.events_in_time(rt(0), rt(std::numeric_limits<std::int64_t>::max())).size(), 5u);
}

TEST(DamagedStore, NonRegularFilesAreRefusedWithoutOpeningThem) {
  TempDir dir;
  const auto fifo = dir.file("fifo.db");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Opening a FIFO for reading would wait for a writer: refused by stat() alone, it returns.
  const auto e = open_failure(fifo, false);
  EXPECT_EQ(e.kind(), core::ErrorKind::data);
  EXPECT_TRUE(contains(e.what(), "not a regular file")) << e.what();
  const auto d = open_failure(dir.file(""), true);
  EXPECT_TRUE(contains(d.what(), "a directory")) << d.what();
}

TEST(DamagedStore, TheResumeBySeqReadRefusesABadRowInsteadOfSkippingIt) {
  // The agent serves with events_after and a coordinator's cursor moves past what it was given: a
  // row left out there would be lost for good.
  TempDir dir;
  const std::pair<std::string, std::string> cases[] = {
      {"UPDATE events SET session_id = 77 WHERE seq = 3", "row seq 3: field 'session_id' names session 77"},
      {"UPDATE events SET flags = 4294967296 WHERE seq = 2", "row seq 2: field 'flags' holds 4294967296"},
      {"UPDATE events SET channel = '' WHERE seq = 4", "row seq 4: field 'channel' is empty"},
  };
  int n = 0;
  for (const auto& [sql, message] : cases) {
    const auto path = make_store(dir, "after" + std::to_string(n++) + ".db");
    edit(path, sql);
    Options read_only;
    read_only.read_only = true;
    const auto store = Store::open(path, read_only);
    try {
      store.events_after(0, 100);
      ADD_FAILURE() << sql << ": no error";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::data);
      EXPECT_TRUE(contains(e.what(), message)) << e.what();
    }
  }
}
