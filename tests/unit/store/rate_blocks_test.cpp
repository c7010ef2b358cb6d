// Raw rate samples in the store: blocks round trip exactly, a store of the previous schema version is
// migrated with its rows kept, merge carries the blocks into a campaign store exactly once, and a
// damaged block is reported naming the table and the row.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/merge.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "m2mlat/store/schema.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

namespace m2mlat::store::rate_blocks_test {
using m2mlat::store::test::contains;

namespace {

using test::make_session;
using test::rt;
using test::TempDir;

constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;

// `n` samples 125 us apart from kT0 + offset, with values that use every byte (signs, extremes).
std::vector<core::RateSample> samples(std::size_t n, std::int64_t offset = 0) {
  std::vector<core::RateSample> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto& s = out[i];
    s.time_ns = kT0 + offset + static_cast<std::int64_t>(i) * 125'000;
    s.bound_ns = static_cast<std::int32_t>(80'000 + i % 1000);
    s.raw = {static_cast<std::int16_t>(static_cast<int>(i % 65536) - 32768),
             static_cast<std::int16_t>(32767 - static_cast<int>(i % 7)), static_cast<std::int16_t>(-1)};
  }
  return out;
}

void expect_same(const std::vector<core::RateSample>& got, const std::vector<core::RateSample>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].time_ns, want[i].time_ns) << i;
    EXPECT_EQ(got[i].bound_ns, want[i].bound_ns) << i;
    EXPECT_EQ(got[i].raw, want[i].raw) << i;
  }
}


TEST(RateBlocks, ATraceRoundTripsThroughBlocksInTimeOrder) {
  TempDir dir;
  auto store = Store::open(dir.file("board.m2mlat"));
  const auto id = store.begin_session(make_session("vehicle"));
  const auto trace = samples(2 * rate_block::kMaxSamples + 17);
  auto blocks = rate_block::split(id, "gyro", core::Clock::realtime, 131.0, trace);
  ASSERT_EQ(blocks.size(), 3u);
  EXPECT_EQ(blocks[1].first_index, rate_block::kMaxSamples);
  // Appended out of order (the later blocks first): the trace still reads back in time order.
  store.append_rate_blocks(std::vector{blocks[2], blocks[0]});
  store.append_rate_blocks(std::vector{blocks[1]});

  const core::RateTrace back = store.rate_trace(id, "gyro");
  EXPECT_EQ(back.clock, core::Clock::realtime);
  EXPECT_EQ(back.counts_per_deg_s, 131.0);
  expect_same(back.samples, trace);
  EXPECT_EQ(store.rate_channels(),
            (std::vector<RateChannel>{{id, "vehicle", "gyro", static_cast<std::int64_t>(trace.size())}}));
  EXPECT_EQ(rate_block::encode(trace).size(), trace.size() * rate_block::kSampleBytes);
  // Another channel or session has none.
  try {
    (void)store.rate_trace(id, "other");
    ADD_FAILURE() << "a missing trace was read";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    EXPECT_TRUE(contains(e.what(), "channel 'other'")) << e.what();
  }
}

TEST(RateBlocks, ABadBlockIsRefusedNamingTheFieldAndNothingIsStored) {
  TempDir dir;
  auto store = Store::open(dir.file("board.m2mlat"));
  const auto id = store.begin_session(make_session("vehicle"));
  auto good = rate_block::split(id, "gyro", core::Clock::realtime, 131.0, samples(10));
  auto unordered = good.front();
  unordered.first_index = 10;
  std::swap(unordered.samples[3], unordered.samples[4]);
  try {
    store.append_rate_blocks(std::vector{good.front(), unordered});
    ADD_FAILURE() << "an unordered block was stored";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_TRUE(contains(e.what(), "rate block 1 of the batch: sample 4")) << e.what();
  }
  auto no_scale = good.front();
  no_scale.counts_per_deg_s = 0;
  EXPECT_THROW(store.append_rate_blocks(std::vector{no_scale}), core::Error);
  EXPECT_TRUE(store.rate_channels().empty());  // the good block of the refused batch too
}

// A version-2 store (the schema before raw samples) made by the first two steps, with a session and
// a loss: opening it migrates it, keeps both (the loss under its id), and it takes raw samples and
// the gyroscope's loss kinds afterwards.
TEST(RateBlocks, AStoreOfThePreviousVersionIsMigratedWithItsRowsKept) {
  TempDir dir;
  const auto path = dir.file("v2.m2mlat");
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
    const auto all = schema::migrations();
    ASSERT_GE(all.size(), 3u);
    EXPECT_EQ(schema::migrate(db, all.first(2)), 2);
    db.exec(
        "INSERT INTO sessions (label, scenario, node, role, config_json, start_clock, start_ns, "
        "software_version) VALUES ('old', 'bench', 'vehicle', 2, '{}', 0, 5, 'm2mlat 0.old')");
    db.exec(
        "INSERT INTO losses (id, session_id, channel, clock, t_ns, first_missing, count, kind) "
        "VALUES (7, 1, 'wheel', 0, 9, 3, 2, 'seqno_gap')");
    db.exec("INSERT INTO origins (origin, event_seq, clock_sample_id, loss_id) VALUES ('abc', 4, 5, 6)");
    // The version-2 schema refuses the gyroscope's loss kinds.
    EXPECT_THROW(db.exec("INSERT INTO losses (session_id, channel, clock, t_ns, first_missing, count, kind) "
                         "VALUES (1, 'gyro', 0, 9, 3, 2, 'missed_period')"),
                 core::Error);
  }
  auto store = Store::open(path);
  EXPECT_EQ(store.schema_version(), schema::latest_version());
  ASSERT_EQ(store.sessions().size(), 1u);
  EXPECT_EQ(store.sessions()[0].label, "old");
  const auto losses = store.losses_after(0, 10);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].id, 7);
  EXPECT_EQ(losses[0].loss.kind, "seqno_gap");
  EXPECT_EQ(store.ingest_cursor("abc"), (IngestCursor{4, 5, 6, 0, 0}));

  const auto id = store.begin_session(make_session("vehicle", "new"));
  store.append_rate_blocks(rate_block::split(id, "gyro", core::Clock::realtime, 131.0, samples(5)));
  Loss missed;
  missed.session_id = id;
  missed.channel = "gyro";
  missed.detected_at = rt(kT0);
  missed.first_missing = 5;
  missed.count = 3;
  missed.kind = "missed_period";
  store.append_losses(std::vector{missed});
  EXPECT_EQ(store.losses(id), std::vector{missed});
  EXPECT_EQ(store.rate_trace(id, "gyro").samples.size(), 5u);
  EXPECT_TRUE(store.integrity_ok());
  store.check_rows();
}

TEST(RateBlocks, MergeCarriesTheBlocksAndLossesExactlyOnce) {
  TempDir dir;
  auto board = Store::open(dir.file("vehicle.m2mlat"));
  const auto id = board.begin_session(make_session("vehicle"));
  const auto first = samples(3 * rate_block::kMaxSamples);
  board.append_rate_blocks(rate_block::split(id, "gyro", core::Clock::realtime, 131.0, first));
  Loss missed;
  missed.session_id = id;
  missed.channel = "gyro";
  missed.detected_at = rt(kT0);
  missed.first_missing = first.size();
  missed.count = 2;
  missed.kind = "missed_period";
  board.append_losses(std::vector{missed});

  auto campaign = Store::open(dir.file("campaign.m2mlat"));
  // chunk 256 -> one block per transaction: the merge resumes block by block.
  const auto a = merge_store(campaign, board.path(), 256);
  EXPECT_EQ(a.rate_blocks, 3);
  EXPECT_EQ(a.losses, 1);
  const auto b = merge_store(campaign, board.path(), 256);
  EXPECT_EQ(b.rate_blocks, 0);
  const auto traces = campaign.rate_channels();
  ASSERT_EQ(traces.size(), 1u);
  EXPECT_EQ(traces[0].samples, static_cast<std::int64_t>(first.size()));
  expect_same(campaign.rate_trace(traces[0].session_id, "gyro").samples, first);

  // The board gains a block after a gap of 2 samples: only that block is taken.
  const auto later = samples(100, static_cast<std::int64_t>(first.size() + 2) * 125'000);
  board.append_rate_blocks(
      rate_block::split(id, "gyro", core::Clock::realtime, 131.0, later, first.size() + 2));
  const auto c = merge_store(campaign, board.path(), 256);
  EXPECT_EQ(c.rate_blocks, 1);
  const auto merged = campaign.rate_trace(traces[0].session_id, "gyro");
  EXPECT_EQ(merged.samples.size(), first.size() + later.size());
  EXPECT_EQ(campaign.losses(traces[0].session_id).size(), 1u);
  const auto blocks = campaign.rate_blocks_after(0, 10);
  ASSERT_EQ(blocks.size(), 4u);
  EXPECT_EQ(blocks.back().block.first_index, first.size() + 2);  // the gap stays visible
}

TEST(RateBlocks, ADamagedBlobIsReportedNamingTheTableAndRow) {
  TempDir dir;
  const auto path = dir.file("damaged.m2mlat");
  std::int64_t id = 0;
  {
    auto store = Store::open(path);
    id = store.begin_session(make_session("vehicle"));
    store.append_rate_blocks(rate_block::split(id, "gyro", core::Clock::realtime, 131.0, samples(20)));
    store.append_rate_blocks(
        rate_block::split(id, "gyro", core::Clock::realtime, 131.0, samples(20, 20 * 125'000), 20));
  }
  {
    // Another tool cuts row 2's BLOB short (CHECK constraints switched off, as SQLite allows).
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    db.exec("PRAGMA ignore_check_constraints = ON");
    db.exec("UPDATE rate_blocks SET samples = substr(samples, 1, 100) WHERE id = 2");
  }
  {
    auto store = Store::open(path);
    try {
      store.check_rows();
      ADD_FAILURE() << "the damaged row passed";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::data);
      EXPECT_TRUE(contains(e.what(), "table 'rate_blocks' row id 2: field 'samples'")) << e.what();
    }
    EXPECT_THROW((void)store.rate_trace(id, "gyro"), core::Error);
  }
  {
    // A BLOB of the right length whose stamps go backwards: found when it is decoded.
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    auto reversed = samples(20, 20 * 125'000);
    std::swap(reversed[0], reversed[19]);
    sqlite::Statement update(db, "UPDATE rate_blocks SET samples = ?1 WHERE id = 2");
    update.bind_blob(1, rate_block::encode(reversed));
    update.step();
  }
  auto store = Store::open(path);
  store.check_rows();  // the row's columns keep the schema's rules
  try {
    (void)store.rate_trace(id, "gyro");
    ADD_FAILURE() << "the damaged BLOB was read";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_TRUE(contains(e.what(), "table 'rate_blocks' row id 2: field 'samples': sample 1")) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::store::rate_blocks_test
