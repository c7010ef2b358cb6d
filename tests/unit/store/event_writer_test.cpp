// The batching writer: commits by size, by age and on demand; the acknowledged point; records the
// store would refuse are refused at add() without disturbing the batch.
#include "m2mlat/store/event_writer.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;
using namespace std::chrono_literals;

namespace {

class Writer : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = std::make_unique<Store>(Store::open(dir_.file("w.m2mlat")));
    session_ = store_->begin_session(make_session("vehicle"));
  }
  WriterOptions options(std::size_t max_batch, core::Duration max_age) {
    WriterOptions o;
    o.max_batch = max_batch;
    o.max_age = max_age;
    o.now = [this] { return now_; };
    return o;
  }
  core::Event event(std::uint64_t n) {
    return make_event("vehicle", "wheel", static_cast<std::int64_t>(n) * 1000, n);
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  std::int64_t session_ = 0;
  core::Duration now_{1'000'000'000};  // the injected monotonic clock
};

}  // namespace

TEST_F(Writer, CommitsWhenTheBatchIsFull) {
  EventWriter writer(*store_, session_, options(4, 1h));
  EXPECT_EQ(writer.last_committed_seq(), 0);
  for (std::uint64_t n = 1; n <= 3; ++n) writer.add(event(n));
  EXPECT_EQ(writer.pending(), 3u);
  EXPECT_EQ(store_->last_seq(), 0);  // nothing visible before the commit
  writer.add(event(4));
  EXPECT_EQ(writer.pending(), 0u);
  EXPECT_EQ(writer.last_committed_seq(), 4);
  EXPECT_EQ(store_->last_seq(), 4);
  for (std::uint64_t n = 5; n <= 10; ++n) writer.add(event(n));
  EXPECT_EQ(writer.last_committed_seq(), 8);
  EXPECT_EQ(writer.pending(), 2u);
  EXPECT_EQ(writer.committed_events(), 8u);
}

TEST_F(Writer, CommitsWhenTheOldestRecordIsOldEnough) {
  EventWriter writer(*store_, session_, options(1000, 50ms));
  writer.add(event(1));
  now_ += 30ms;
  writer.add(event(2));
  EXPECT_FALSE(writer.poll());
  EXPECT_EQ(writer.pending(), 2u);
  now_ += 19ms;  // 49 ms after the first record
  EXPECT_FALSE(writer.poll());
  now_ += 1ms;
  EXPECT_TRUE(writer.poll());
  EXPECT_EQ(writer.last_committed_seq(), 2);
  EXPECT_FALSE(writer.poll());  // nothing buffered
  // The age counts from the first record of the new batch, and add() commits an old batch too.
  now_ += 1h;
  writer.add(event(3));
  EXPECT_EQ(writer.pending(), 1u);
  now_ += 50ms;
  writer.add(event(4));
  EXPECT_EQ(writer.pending(), 0u);
  EXPECT_EQ(writer.last_committed_seq(), 4);
}

TEST_F(Writer, FlushAndDestructorCommit) {
  {
    EventWriter writer(*store_, session_, options(1000, 1h));
    writer.add(event(1));
    writer.add(event(2));
    EXPECT_EQ(writer.flush(), (AppendResult{1, 2}));
    EXPECT_EQ(writer.flush(), (AppendResult{0, 0}));
    writer.add(event(3));
  }
  EXPECT_EQ(store_->last_seq(), 3);
  // A new writer starts from the store's acknowledged point.
  EventWriter again(*store_, session_, options(1000, 1h));
  EXPECT_EQ(again.last_committed_seq(), 3);
}

TEST_F(Writer, LossesAndClockSamplesCommitWithTheEvents) {
  EventWriter writer(*store_, session_, options(3, 1h));
  writer.add(event(1));
  writer.add(Loss{session_, "wheel", rt(3000), 2, 1, "seqno_gap"});
  EXPECT_EQ(store_->losses().size(), 0u);
  writer.add(ClockSample{session_, rt(3000), "chrony", 5, 100, 20, true, "{}"});
  EXPECT_EQ(writer.pending(), 0u);
  EXPECT_EQ(store_->losses().size(), 1u);
  EXPECT_EQ(store_->clock_samples().size(), 1u);
  EXPECT_EQ(store_->last_seq(), 1);
}

TEST_F(Writer, RefusedRecordsAreNotBuffered) {
  EventWriter writer(*store_, session_, options(1000, 1h));
  writer.add(event(1));
  auto wrong_node = event(2);
  wrong_node.node = "operator";
  EXPECT_THROW(writer.add(wrong_node), core::Error);
  auto no_channel = event(2);
  no_channel.channel.clear();
  EXPECT_THROW(writer.add(no_channel), core::Error);
  EXPECT_THROW(writer.add(Loss{session_ + 1, "wheel", rt(1), 2, 1, "seqno_gap"}), core::Error);
  EXPECT_THROW(writer.add(ClockSample{session_, rt(1), "chrony", 0, 0, 0, true, "{"}), core::Error);
  EXPECT_EQ(writer.pending(), 1u);
  writer.flush();
  EXPECT_EQ(store_->event_count(), 1);
}

TEST_F(Writer, NeedsAnOpenSession) {
  EXPECT_THROW(EventWriter(*store_, session_ + 1), core::Error);
  store_->end_session(session_, store_->session(session_)->start + 1s);
  EXPECT_THROW(EventWriter(*store_, session_), core::Error);
}

// A commit that fails keeps the batch, and it can be retried once the cause is gone: here another
// connection holds the write lock longer than the busy timeout.
TEST_F(Writer, AFailedCommitKeepsTheBatchForARetry) {
  auto impatient = Store::open(store_->path(), Options{.busy_timeout_ms = 20});
  EventWriter writer(impatient, session_, options(1000, 1h));
  writer.add(event(1));
  writer.add(event(2));
  {
    auto other = sqlite::Database::open(store_->path(), sqlite::Database::Mode::read_write);
    sqlite::Transaction lock(other);
    try {
      writer.flush();
      ADD_FAILURE() << "the commit did not wait for the lock";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::io) << e.what();
    }
    EXPECT_EQ(writer.pending(), 2u);
    EXPECT_EQ(writer.last_committed_seq(), 0);
  }  // lock released
  EXPECT_EQ(writer.flush(), (AppendResult{1, 2}));
  EXPECT_EQ(store_->event_count(), 2);
  EXPECT_TRUE(store_->integrity_ok());
}
