// Rows checked by seq range (store/event_ranges.hpp): a read checks the events of the ranges its
// spans lie in, once per Store, so a damaged row in a range that is read is refused, one in a range
// that is not read leaves reads elsewhere as they are and is refused once read; an event outside
// every span (inserted by another tool without one) is refused by every read, also when it was
// inserted after the Store's first read.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;
constexpr std::int64_t kBatches = 3, kPerBatch = 10;  // a session's events: seqs in 3 ranges of 10

// Two sessions one after the other, each of three batches on two channels, 1 ms apart: session 1
// holds seqs 1..30 (t from kT0), session 2 seqs 31..60 (t from kT0 + 1 s).
std::string make_batched_store(const TempDir& dir, const std::string& name) {
  const auto path = dir.file(name);
  auto store = Store::open(path);
  for (int s = 0; s < 2; ++s) {
    const auto id = store.begin_session(make_session("vehicle"));
    for (std::int64_t b = 0; b < kBatches; ++b) {
      std::vector<core::Event> batch;
      for (std::int64_t i = 0; i < kPerBatch; ++i) {
        const std::int64_t k = b * kPerBatch + i;
        batch.push_back(make_event("vehicle", k % 2 == 0 ? "wheel" : "motion",
                                   kT0 + s * 1'000'000'000 + k * 1'000'000,
                                   static_cast<std::uint64_t>(k + 1)));
      }
      store.append_events(id, batch);
    }
  }
  return path;
}

Store open_read_only(const std::string& path) {
  Options options;
  options.read_only = true;
  return Store::open(path, options);
}

EventFilter of_session(std::int64_t id) {
  EventFilter filter;
  filter.session_id = id;
  return filter;
}

const core::TimePoint kFrom = rt(std::numeric_limits<std::int64_t>::min());
const core::TimePoint kTo = rt(std::numeric_limits<std::int64_t>::max());

// The message of the data error a read throws ("" if it throws none).
template <typename Read>
std::string refusal(Read&& read) {
  try {
    read();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data) << e.what();
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CheckedRanges, ADamagedRowIsRefusedByTheReadsThatSeeItOnly) {
  TempDir dir;
  struct Case {
    std::string sql, message;
  };
  // Each in session 1's second batch (seqs 11..20).
  const Case cases[] = {
      {"UPDATE events SET edge = 2 WHERE seq = 13", "table 'events' row seq 13: field 'edge' holds 2"},
      {"DELETE FROM events WHERE seq = 14",
       "table 'events' holds 9 rows, its spans (table 'event_spans') count 10, from seq 11 to 20"},
      // Moved to a session that does not exist: the count is right, the row is not.
      {"UPDATE events SET session_id = 9 WHERE seq = 15",
       "table 'events' row seq 15: field 'session_id' holds 9"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const auto path = make_batched_store(dir, "case" + std::to_string(n++) + ".db");
    edit(path, c.sql);
    const auto store = open_read_only(path);
    // Session 2 and session 1's first batch read as before: their ranges hold no damaged row.
    EXPECT_EQ(store.timestamps(kFrom, kTo, of_session(2)).seq.size(), 30u) << c.sql;
    EXPECT_EQ(store.events_in_time(rt(kT0), rt(kT0 + 9'000'000), of_session(1)).size(), 10u) << c.sql;
    // A read that sees the damaged range is refused, naming the store and the row; again when
    // asked again, and a read through the whole time range too.
    for (int again = 0; again < 2; ++again) {
      const auto message = refusal([&] { store.timestamps(kFrom, kTo, of_session(1)); });
      EXPECT_TRUE(contains(message, path)) << message;
      EXPECT_TRUE(contains(message, c.message)) << c.sql << ": " << message;
    }
    EXPECT_TRUE(contains(refusal([&] { store.events_in_time(kFrom, kTo); }), c.message)) << c.sql;
    EXPECT_TRUE(contains(refusal([&] { store.check_rows(); }), c.message)) << c.sql;
    // The reads elsewhere still give what they gave.
    EXPECT_EQ(store.timestamps(kFrom, kTo, of_session(2)).seq.size(), 30u) << c.sql;
  }
}

TEST(CheckedRanges, AnEventInNoSpanIsRefusedByEveryRead) {
  TempDir dir;
  // Where another tool's INSERT puts it (after the last span), and with a seq in a hole between
  // two ranges (session 1's second batch deleted with its spans: a hole, which is no damage).
  const auto appended = make_batched_store(dir, "appended.db");
  edit(appended,
       "INSERT INTO events (session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
       "VALUES (1, 'wheel', 1, 0, 9, 9, 9, 0)");
  const auto in_hole = make_batched_store(dir, "hole.db");
  edit(in_hole,
       "DELETE FROM events WHERE seq BETWEEN 11 AND 20; DELETE FROM event_spans WHERE first_seq >= 11 "
       "AND last_seq <= 20");
  {
    const auto store = open_read_only(in_hole);
    EXPECT_EQ(store.timestamps(kFrom, kTo, of_session(1)).seq.size(), 20u);
    EXPECT_NO_THROW(store.check_rows());
  }
  edit(in_hole,
       "INSERT INTO events (seq, session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
       "VALUES (15, 2, 'wheel', 1, 0, 9, 9, 9, 0)");
  const std::pair<std::string, std::string> cases[] = {
      {appended,
       "table 'events' holds 11 rows, its spans (table 'event_spans') count 10, from seq 51 to 61 (seq 61 "
       "lies in no span)"},
      {in_hole,
       "table 'events' holds 21 rows, its spans (table 'event_spans') count 20, from seq 1 to 30 (seq 15 "
       "lies in no span)"},
  };
  for (const auto& [path, message] : cases) {
    const auto store = open_read_only(path);
    for (const std::int64_t session : {1, 2}) {
      const auto got = refusal([&] { store.timestamps(kFrom, kTo, of_session(session)); });
      EXPECT_TRUE(contains(got, path)) << got;
      EXPECT_TRUE(contains(got, message)) << got;
    }
    EXPECT_TRUE(contains(refusal([&] { store.events_in_time(rt(kT0), rt(kT0)); }), message));
  }
}

TEST(CheckedRanges, RowsWrittenAfterTheFirstReadAreCheckedByTheNextOne) {
  TempDir dir;
  const auto path = make_batched_store(dir, "live.db");
  const auto reader = open_read_only(path);
  EXPECT_EQ(reader.timestamps(kFrom, kTo).seq.size(), 60u);  // every range checked
  {
    // A recorder's new batch: a new range, read and checked by the next read.
    auto writer = Store::open(path);
    const auto id = writer.begin_session(make_session("vehicle"));
    writer.append_events(id, std::vector{make_event("vehicle", "wheel", kT0 + 5'000'000'000, 1),
                                         make_event("vehicle", "wheel", kT0 + 5'000'000'001, 2)});
  }
  EXPECT_EQ(reader.timestamps(kFrom, kTo).seq.size(), 62u);
  EXPECT_EQ(reader.timestamps(kFrom, kTo, of_session(3)).seq.size(), 2u);
  // Another tool's event without a span, after the reader's first read: refused all the same.
  edit(path,
       "INSERT INTO events (session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
       "VALUES (1, 'wheel', 1, 0, 9, 9, 9, 0)");
  EXPECT_TRUE(
      contains(refusal([&] { reader.timestamps(kFrom, kTo, of_session(1)); }), "(seq 63 lies in no span)"));
}
