// Markers in the store: they round trip exactly (optional fields too), a bad one is refused naming the
// field with nothing stored, a store of the previous schema version is migrated with its rows kept, and
// merge carries markers into a campaign store exactly once.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/merge.hpp"
#include "m2mlat/store/schema.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

namespace m2mlat::store::markers_test {
using m2mlat::store::test::contains;

namespace {

using test::make_session;
using test::rt;
using test::TempDir;

constexpr std::int64_t kT0 = 1'764'000'000'000'000'000;

MarkerRecord mark(std::int64_t session, const std::string& name, std::int64_t offset_ns) {
  MarkerRecord m;
  m.session_id = session;
  m.name = name;
  m.time = rt(kT0 + offset_ns);
  m.source = "kernel";
  m.key = "cmd-" + std::to_string(offset_ns);
  m.origin = "127.0.0.1:40000";
  return m;
}


TEST(StoreMarkers, RoundTripWithAndWithoutTheOptionalFields) {
  TempDir dir;
  auto store = Store::open(dir.file("board.m2mlat"));
  const auto id = store.begin_session(make_session("operator"));
  auto a = mark(id, "planner_out", 2'000);
  a.sender_ns = kT0 + 1'500;
  a.uncertainty_ns = 0;
  auto b = mark(id, "joystick", 1'000);  // earlier: markers() orders by time
  b.key.clear();
  b.source = "receiver";
  store.append_markers(std::vector{a, b});

  const auto by_id = store.markers_after(0, 10);
  ASSERT_EQ(by_id.size(), 2u);
  EXPECT_EQ(by_id[0].marker, a);
  EXPECT_EQ(by_id[1].marker, b);
  EXPECT_LT(by_id[0].id, by_id[1].id);
  EXPECT_EQ(store.markers_after(by_id[0].id, 10).size(), 1u);

  const auto by_time = store.markers(id);
  ASSERT_EQ(by_time.size(), 2u);
  EXPECT_EQ(by_time[0].marker.name, "joystick");
  EXPECT_FALSE(by_time[0].marker.sender_ns);
  EXPECT_FALSE(by_time[0].marker.uncertainty_ns);
  EXPECT_EQ(by_time[1].marker.sender_ns, kT0 + 1'500);
  EXPECT_TRUE(store.markers(id + 1).empty());
  store.check_rows();
}

TEST(StoreMarkers, ABadMarkerIsRefusedNamingTheFieldAndNothingIsStored) {
  TempDir dir;
  auto store = Store::open(dir.file("board.m2mlat"));
  const auto id = store.begin_session(make_session("operator"));
  const auto good = mark(id, "ok", 1);
  const auto refused = [&](MarkerRecord bad, const std::string& field) {
    try {
      store.append_markers(std::vector{good, bad});
      ADD_FAILURE() << "accepted a marker with a bad " << field;
    } catch (const core::Error& e) {
      EXPECT_TRUE(contains(e.what(), field)) << e.what();
      EXPECT_TRUE(contains(e.what(), "marker 1 of the batch")) << e.what();
    }
  };
  auto no_name = mark(id, "", 2);
  refused(no_name, "'name'");
  auto bad_source = mark(id, "x", 2);
  bad_source.source = "Kernel Stamp";
  refused(bad_source, "'source'");
  auto negative = mark(id, "x", 2);
  negative.uncertainty_ns = -1;
  refused(negative, "'uncertainty_ns'");
  EXPECT_THROW(store.append_markers(std::vector{mark(id + 7, "x", 3)}), core::Error);  // no such session
  EXPECT_TRUE(store.markers().empty());
}

// A version-3 store (the schema before markers) with a session and a cursor: opening it migrates it,
// keeps both, and it takes markers afterwards.
TEST(StoreMarkers, AStoreOfThePreviousVersionIsMigratedWithItsRowsKept) {
  TempDir dir;
  const auto path = dir.file("v3.m2mlat");
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
    const auto all = schema::migrations();
    ASSERT_GE(all.size(), 4u);
    EXPECT_EQ(schema::migrate(db, all.first(3)), 3);
    db.exec(
        "INSERT INTO sessions (label, scenario, node, role, config_json, start_clock, start_ns, "
        "software_version) VALUES ('old', 'bench', 'vehicle', 2, '{}', 0, 5, 'm2mlat 0.old')");
    db.exec(
        "INSERT INTO origins (origin, event_seq, clock_sample_id, loss_id, rate_block_id) "
        "VALUES ('abc', 4, 5, 6, 7)");
  }
  auto store = Store::open(path);
  EXPECT_EQ(store.schema_version(), schema::latest_version());
  ASSERT_EQ(store.sessions().size(), 1u);
  EXPECT_EQ(store.ingest_cursor("abc"), (IngestCursor{4, 5, 6, 7, 0}));
  const auto id = store.begin_session(make_session("vehicle", "new"));
  store.append_markers(std::vector{mark(id, "actuator_cmd", 9)});
  EXPECT_EQ(store.markers().size(), 1u);
  EXPECT_TRUE(store.integrity_ok());
  store.check_rows();
}

TEST(StoreMarkers, MergeCarriesMarkersExactlyOnceWithTheirSessions) {
  TempDir dir;
  auto board = Store::open(dir.file("operator.m2mlat"));
  const auto id = board.begin_session(make_session("operator"));
  std::vector<MarkerRecord> first;
  for (int i = 0; i < 5; ++i) first.push_back(mark(id, "sent", i * 10'000'000));
  board.append_markers(first);

  auto campaign = Store::open(dir.file("campaign.m2mlat"));
  const auto a = merge_store(campaign, board.path(), 2);  // chunks of 2: resumes by the cursor
  EXPECT_EQ(a.markers, 5);
  const auto b = merge_store(campaign, board.path(), 2);
  EXPECT_EQ(b.markers, 0);
  board.append_markers(std::vector{mark(id, "sent", 99)});
  EXPECT_EQ(merge_store(campaign, board.path()).markers, 1);

  const auto merged = campaign.markers();
  ASSERT_EQ(merged.size(), 6u);
  const auto sessions = campaign.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0].node, "operator");
  for (const auto& m : merged) EXPECT_EQ(m.marker.session_id, sessions[0].id);
  EXPECT_EQ(campaign.ingest_cursor(board.store_id()).markers, board.markers_after(0, 100).back().id);

  // A batch naming the markers again (an agent's page given twice) changes nothing.
  IngestBatch again;
  again.origin = board.store_id();
  again.sessions = board.sessions();
  again.markers = board.markers_after(0, 100);
  campaign.ingest(again);
  EXPECT_EQ(campaign.markers().size(), 6u);
}

// A row another tool wrote with a negative uncertainty is reported naming the table, row and field.
TEST(StoreMarkers, ARowBreakingTheSchemaIsReported) {
  TempDir dir;
  const auto path = dir.file("edited.m2mlat");
  {
    auto store = Store::open(path);
    const auto id = store.begin_session(make_session("operator"));
    store.append_markers(std::vector{mark(id, "x", 1)});
  }
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    db.exec("PRAGMA ignore_check_constraints = ON");
    db.exec("UPDATE markers SET uncertainty_ns = -5");
  }
  auto store = Store::open(path);
  try {
    store.check_rows();
    ADD_FAILURE() << "accepted a broken row";
  } catch (const core::Error& e) {
    EXPECT_TRUE(contains(e.what(), "table 'markers'")) << e.what();
    EXPECT_TRUE(contains(e.what(), "uncertainty_ns")) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::store::markers_test
