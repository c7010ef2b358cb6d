// The archive against a real PostgreSQL server (tests/support/pg_server.bash: initdb and pg_ctl in a
// temporary folder, a unix socket only; skipped when Debian's postgresql is not installed): the
// schema created and migrated on first use, a newer schema refused, and a campaign store pushed and
// read back row for row (uint64 kernel counters and int64 ns exact), twice without duplicates.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "m2mlat/archive/push.hpp"
#include "m2mlat/archive/read.hpp"
#include "m2mlat/archive/schema.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

namespace m2mlat::archive {
namespace {

const std::string kServerScript = std::string(M2MLAT_TEST_DATA) + "/../support/pg_server.bash";

// One server for the suite; each test gets a database of its own.
class ArchiveServer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    FILE* out = popen(("bash " + kServerScript + " start " + dir_->path().string()).c_str(), "r");
    char line[4096] = {};
    const bool read = out != nullptr && fgets(line, sizeof line, out) != nullptr;
    const int status = out != nullptr ? pclose(out) : -1;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 77) {
      skip_ = "initdb not found: Debian's postgresql package is not installed";
      return;
    }
    ASSERT_TRUE(read && status == 0) << "the PostgreSQL server did not start";
    url_ = line;
    while (!url_.empty() && url_.back() == '\n') url_.pop_back();
  }
  static void TearDownTestSuite() {
    if (dir_ == nullptr) return;
    if (!url_.empty()) std::system(("bash " + kServerScript + " stop " + dir_->path().string()).c_str());
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!skip_.empty()) GTEST_SKIP() << skip_;
    // A fresh database named after the test.
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::string db;
    for (const char ch : name) db += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    auto admin = Connection::open(url_);
    admin.exec("DROP DATABASE IF EXISTS " + db);
    admin.exec("CREATE DATABASE " + db);
    url_db_ = url_;
    url_db_.replace(url_db_.find("/lab?"), 5, "/" + db + "?");
  }
  Connection connect() const { return Connection::open(url_db_); }

  static inline testing::TempDir* dir_ = nullptr;
  static inline std::string url_, skip_;
  std::string url_db_;
  testing::TempDir local_;
};

TEST_F(ArchiveServer, CreatesTheSchemaOnFirstUseAndMigratesOnce) {
  auto c = connect();
  EXPECT_EQ(schema_version(c), 0);
  EXPECT_TRUE(list_campaigns(c, {}).empty());  // no tables yet: an empty archive, not an error
  EXPECT_EQ(migrate(c), kSchemaVersion);
  EXPECT_EQ(schema_version(c), kSchemaVersion);
  EXPECT_EQ(migrate(c), kSchemaVersion);  // again: nothing to do, no error
  const auto tables = c.exec(
      "SELECT string_agg(table_name, ',' ORDER BY table_name) FROM information_schema.tables "
      "WHERE table_schema = 'm2mlat'");
  EXPECT_EQ(tables.at(0, 0), "campaigns,clock_samples,events,losses,meta,push_cursors,rate_blocks,sessions");
}

TEST_F(ArchiveServer, MigratesAVersionOneArchiveKeepingItsRows) {
  auto c = connect();
  EXPECT_EQ(migrate(c, 1), 1);
  c.exec("INSERT INTO m2mlat.campaigns (store_id, name) VALUES ('00ff', 'old')");
  c.exec("INSERT INTO m2mlat.push_cursors (campaign_id, events) SELECT id, 42 FROM m2mlat.campaigns");
  EXPECT_EQ(migrate(c), kSchemaVersion);
  EXPECT_EQ(c.exec("SELECT name FROM m2mlat.campaigns").at(0, 0), "old");
  EXPECT_EQ(c.exec("SELECT events || '/' || rate_blocks FROM m2mlat.push_cursors").at(0, 0), "42/0");
  EXPECT_EQ(c.exec("SELECT count(*) FROM m2mlat.rate_blocks").at(0, 0), "0");
}

TEST_F(ArchiveServer, RefusesANewerSchema) {
  auto c = connect();
  migrate(c);
  c.exec("UPDATE m2mlat.meta SET value = '99' WHERE key = 'schema_version'");
  try {
    migrate(c);
    FAIL() << "a newer schema was accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("schema version 99"), std::string::npos) << e.what();
  }
  EXPECT_EQ(schema_version(c), 99);  // the refused migration changed nothing
}

TEST_F(ArchiveServer, PushesAndReadsBackEveryRowExactlyOnce) {
  const auto path = local_.file("spring.db");
  {
    auto s = store::Store::open(path);
    store::Session session;
    session.node = "vehicle";
    session.scenario = "urban";
    session.label = "run-1";
    session.role = core::Role::effect;
    session.start = core::TimePoint::from_ns(core::Clock::realtime, 1'780'272'000'123'456'789);
    const auto id = s.begin_session(session);
    store::Batch batch;
    batch.session_id = id;
    for (int i = 0; i < 7; ++i) {
      core::Event e;
      e.node = "vehicle";
      e.channel = i % 2 ? "wheel" : "tab\there";
      e.edge = i % 2 ? core::Edge::rising : core::Edge::falling;
      e.time =
          core::TimePoint::from_ns(core::Clock::realtime, 1'780'272'000'123'456'789 + i * 1'000'000'007LL);
      e.seqno =
          std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(i);  // above int64's range
      e.line_seqno = static_cast<std::uint64_t>(i + 1);
      e.flags = 0xffffffffu;
      batch.events.push_back(e);
    }
    store::ClockSample sample;
    sample.session_id = id;
    sample.time = session.start;
    sample.source = "chrony";
    sample.offset_ns = -1234;
    sample.max_error_ns = 56789;
    sample.est_error_ns = 321;
    sample.synchronised = true;
    sample.detail_json = R"({"stratum":2})";
    batch.clock_samples.push_back(sample);
    store::Loss loss;
    loss.session_id = id;
    loss.channel = "wheel";
    loss.detected_at = session.start;
    loss.first_missing = std::numeric_limits<std::uint64_t>::max();
    loss.count = 3;
    loss.kind = "seqno_gap";
    batch.losses.push_back(loss);
    store::RateBlock block;
    block.session_id = id;
    block.channel = "gyro";
    block.counts_per_deg_s = 65.5;
    block.first_index = (1ULL << 62) + 7;  // the store takes < 2^63
    for (int i = 0; i < 3; ++i)
      block.samples.push_back({session.start.ns() + i * 1'000'000,
                               2'500,
                               {static_cast<std::int16_t>(-32768 + i), static_cast<std::int16_t>(32767 - i),
                                static_cast<std::int16_t>(i)}});
    batch.rate_blocks.push_back(block);
    s.append(batch);
    s.end_session(id, batch.events.back().time);
  }
  auto c = connect();
  PushOptions options;
  options.rig = "rig-7";
  options.batch_rows = 3;  // several transactions
  const auto first = push(path, c, options);
  EXPECT_EQ(first.name, "spring");
  EXPECT_FALSE(first.resumed);
  EXPECT_EQ(first.events, 7);
  EXPECT_EQ(first.batches, 3);
  EXPECT_EQ(first.clock_samples, 1);
  EXPECT_EQ(first.losses, 1);
  EXPECT_EQ(first.rate_blocks, 1);
  EXPECT_EQ(first.sessions, 1);
  const auto again = push(path, c, {});
  EXPECT_TRUE(again.resumed);
  EXPECT_EQ(again.events + again.clock_samples + again.losses + again.sessions, 0);
  EXPECT_EQ(again.total_events, 7);

  CampaignFilter filter;
  filter.rigs = {"rig-7"};
  const auto campaigns = list_campaigns(c, filter);
  ASSERT_EQ(campaigns.size(), 1u);
  EXPECT_TRUE(campaigns[0].complete);
  EXPECT_EQ(campaigns[0].created_ns, 1'780'272'000'123'456'789);
  ASSERT_EQ(campaigns[0].scenarios.size(), 1u);
  EXPECT_EQ(campaigns[0].scenarios[0].events, 7);
  filter.rigs = {"another-rig"};
  EXPECT_TRUE(list_campaigns(c, filter).empty());

  auto copy = store::Store::open(local_.file("copy.db"));
  read_campaign(c, campaigns[0], scenario_names(campaigns), copy, 2);
  store::Options read_only;
  read_only.read_only = true;
  const auto original = store::Store::open(path, read_only);
  EXPECT_EQ(copy.events_after(0, 100), original.events_after(0, 100));
  EXPECT_EQ(copy.clock_samples(), original.clock_samples());
  EXPECT_EQ(copy.losses(), original.losses());
  // The samples bit for bit: their BLOB layout compared.
  EXPECT_EQ(store::rate_block::encode(copy.rate_blocks_after(0, 10).at(0).block.samples),
            store::rate_block::encode(original.rate_blocks_after(0, 10).at(0).block.samples));
  EXPECT_EQ(copy.rate_blocks_after(0, 10).at(0).block.first_index, (1ULL << 62) + 7);
  EXPECT_EQ(copy.rate_blocks_after(0, 10).at(0).block.counts_per_deg_s, 65.5);
  auto sessions = copy.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(sessions[0], original.sessions()[0]);
}

TEST_F(ArchiveServer, AFailedBatchLeavesTheCursorWhereItWas) {
  const auto path = local_.file("autumn.db");
  {
    auto s = store::Store::open(path);
    store::Session session;
    session.node = "operator";
    session.scenario = "s";
    session.start = core::TimePoint::from_ns(core::Clock::realtime, 1'000);
    const auto id = s.begin_session(session);
    std::vector<core::Event> events(5);
    for (std::size_t i = 0; i < events.size(); ++i) {
      events[i].node = "operator";
      events[i].channel = "wheel";
      events[i].time = core::TimePoint::from_ns(core::Clock::realtime, 2'000 + static_cast<std::int64_t>(i));
    }
    s.append_events(id, events);
  }
  auto c = connect();
  migrate(c);
  // A row the archive already holds under the next seq (as a concurrent writer might): the batch
  // that would copy it fails on the primary key, and its transaction takes nothing with it.
  PushOptions options;
  options.batch_rows = 2;
  push(path, c, options);
  c.exec("DELETE FROM m2mlat.events WHERE seq > 2");
  c.exec("UPDATE m2mlat.push_cursors SET events = 2, complete = false");
  c.exec(
      "INSERT INTO m2mlat.events SELECT campaign_id, 4, session_id, node, channel, edge, clock, t_ns, seqno, "
      "line_seqno, flags FROM m2mlat.events WHERE seq = 1");
  EXPECT_THROW(push(path, c, options), core::Error);
  EXPECT_EQ(c.exec("SELECT events FROM m2mlat.push_cursors").at(0, 0), "2");
  EXPECT_EQ(c.exec("SELECT count(*) FROM m2mlat.events").at(0, 0), "3");
  c.exec("DELETE FROM m2mlat.events WHERE seq = 4");
  const auto resumed = push(path, c, options);
  EXPECT_TRUE(resumed.resumed);
  EXPECT_EQ(resumed.events, 3);
  EXPECT_EQ(resumed.total_events, 5);
}

}  // namespace
}  // namespace m2mlat::archive
