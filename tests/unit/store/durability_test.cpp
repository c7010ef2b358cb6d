// Each durability policy opens, sets its synchronous level, writes and reads back; a reader and a
// writer share one file.
#include <gtest/gtest.h>

#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/event_writer.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

TEST(StoreDurability, EveryPolicyOpensWritesAndReads) {
  struct Case {
    Durability durability;
    int synchronous;  // SQLite's level
  };
  for (const auto& c : {Case{Durability::full, 2}, Case{Durability::normal, 1}, Case{Durability::off, 0}}) {
    SCOPED_TRACE(to_string(c.durability));
    TempDir dir;
    const auto path = dir.file("d.m2mlat");
    const Options options{.durability = c.durability};
    std::int64_t session = 0;
    {
      auto store = Store::open(path, options);
      EXPECT_EQ(store.synchronous(), c.synchronous);
      EXPECT_EQ(store.journal_mode(), "wal");
      session = store.begin_session(make_session("vehicle"));
      EXPECT_EQ(store.append_events(session, std::vector{make_event("vehicle", "wheel", 1, 1),
                                                         make_event("vehicle", "wheel", 2, 2)}),
                1);
    }
    auto store = Store::open(path, options);
    EXPECT_EQ(store.last_seq(), 2);
    EXPECT_EQ(store.append_events(session, std::vector{make_event("vehicle", "wheel", 3, 3)}), 3);
    EXPECT_TRUE(store.integrity_ok());
  }
}

TEST(StoreDurability, PolicyNames) {
  for (auto d : {Durability::full, Durability::normal, Durability::off})
    EXPECT_EQ(parse_durability(to_string(d)), d);
  EXPECT_THROW(parse_durability("fsync"), core::Error);
}

// A recorder writes while a server reads through its own (read-only) connection: the reader sees
// each commit as it happens and never a batch in progress.
TEST(StoreDurability, AReaderSeesCommitsOfAWriter) {
  TempDir dir;
  const auto path = dir.file("shared.m2mlat");
  auto writer_store = Store::open(path);
  const auto session = writer_store.begin_session(make_session("vehicle"));
  auto reader = Store::open(path, Options{.read_only = true});
  auto second_writer = Store::open(path);

  WriterOptions options;
  options.max_batch = 10;
  options.max_age = std::chrono::hours(1);
  EventWriter writer(writer_store, session, options);
  for (int i = 1; i <= 25; ++i) {
    writer.add(make_event("vehicle", "wheel", i, static_cast<std::uint64_t>(i)));
    EXPECT_EQ(reader.last_seq(), writer.last_committed_seq());
  }
  EXPECT_EQ(reader.last_seq(), 20);
  writer.flush();
  EXPECT_EQ(reader.events_after(20, 100).size(), 5u);
  // A second writing connection appends after the first; sequence numbers stay store-wide.
  EXPECT_EQ(second_writer.append_events(session, std::vector{make_event("vehicle", "wheel", 99, 99)}), 26);
  EXPECT_EQ(reader.last_seq(), 26);
  EXPECT_TRUE(reader.integrity_ok());
}
