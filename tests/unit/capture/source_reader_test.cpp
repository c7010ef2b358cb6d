// The reading thread: its queue is bounded (it stops reading rather than grow), it hands events over
// in order and reuses its chunks, a drain on stop reads the source dry, a failure is reported with
// what was read before it; and the latency histogram's quantiles.
#include "m2mlat/capture/source_reader.hpp"

#include <gtest/gtest.h>
#include <poll.h>

#include <chrono>
#include <mutex>
#include <thread>

#include "m2mlat/capture/latency_histogram.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

using namespace std::chrono_literals;

// A source with `available` events ready (numbered from 1), read from the reader's thread while the
// test adds more or checks how much was read. Not pollable: the reader calls read() every 1 ms.
class CountingSource final : public Source {
 public:
  void read(ReadResult& out, std::size_t max_events) override {
    std::lock_guard lock(mutex_);
    ++reads_;
    if (fail_after_ > 0 && next_ > fail_after_) throw core::Error(core::ErrorKind::io, "device gone");
    for (std::size_t i = 0; i < max_events && next_ <= available_; ++i) {
      auto& e = out.events.emplace_back();
      e.node = "vehicle";
      e.channel = "wheel";
      e.time = core::TimePoint::from_ns(core::Clock::realtime, static_cast<std::int64_t>(next_));
      e.seqno = e.line_seqno = next_++;
    }
  }
  int fd() const override { return -1; }
  core::Duration poll_interval() const override { return 1ms; }
  std::vector<std::string> describe() const override { return {"counting"}; }
  std::vector<std::string> channels() const override { return {"wheel"}; }

  void add(std::uint64_t n) {
    std::lock_guard lock(mutex_);
    available_ += n;
  }
  std::uint64_t read_so_far() const {
    std::lock_guard lock(mutex_);
    return next_ - 1;
  }
  void fail_after(std::uint64_t n) {
    std::lock_guard lock(mutex_);
    fail_after_ = n;
  }

 private:
  mutable std::mutex mutex_;
  std::uint64_t available_ = 0, next_ = 1, reads_ = 0, fail_after_ = 0;
};

// Waits (up to 5 s) until `done` holds.
template <typename F>
bool eventually(F done) {
  for (int i = 0; i < 5000; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(1ms);
  }
  return done();
}

std::vector<std::uint64_t> seqnos(const std::vector<std::unique_ptr<ReadResult>>& chunks) {
  std::vector<std::uint64_t> out;
  for (const auto& c : chunks)
    for (const auto& e : c->events) out.push_back(e.seqno);
  return out;
}

TEST(SourceReader, TheQueueIsBoundedAndHandsEventsOverInOrder) {
  CountingSource source;
  source.add(10'000);
  SourceReader reader(source, {100, 4, 0ms, 150});
  // Four chunks of 100: the reader fills them and then stops reading (the kernel would buffer and,
  // once full, drop the oldest with a seqno gap), instead of growing.
  ASSERT_TRUE(eventually([&] { return source.read_so_far() == 400; }));
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(source.read_so_far(), 400u);
  EXPECT_EQ(reader.status().events, 400u);
  pollfd fd{reader.fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&fd, 1, 0), 1);  // more than wake_events are queued
  reader.clear_wake();

  std::vector<std::unique_ptr<ReadResult>> taken;
  reader.take(taken);
  EXPECT_EQ(reader.status().events, 0u);
  auto got = seqnos(taken);
  ASSERT_EQ(got.size(), 400u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], i + 1);
  reader.give_back(taken);
  EXPECT_TRUE(taken.empty());
  ASSERT_TRUE(eventually([&] { return source.read_so_far() == 800; }));
  reader.take(taken);
  got = seqnos(taken);
  ASSERT_EQ(got.size(), 400u);
  EXPECT_EQ(got.front(), 401u);
  EXPECT_EQ(got.back(), 800u);
}

TEST(SourceReader, AStopWithDrainReadsTheSourceDryEvenThroughAFullQueue) {
  CountingSource source;
  SourceReader reader(source, {100, 3, 0ms, 100});
  source.add(1000);  // more than the queue holds: the consumer must give chunks back meanwhile
  reader.stop(true);
  std::vector<std::unique_ptr<ReadResult>> taken;
  std::vector<std::uint64_t> got;
  ASSERT_TRUE(eventually([&] {
    const bool ended = reader.status().ended;
    reader.take(taken);
    for (auto s : seqnos(taken)) got.push_back(s);
    reader.give_back(taken);
    return ended;
  }));
  ASSERT_EQ(got.size(), 1000u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], i + 1);
  EXPECT_EQ(reader.error(), nullptr);
}

TEST(SourceReader, AStopWithoutDrainEndsAtOnce) {
  CountingSource source;
  SourceReader reader(source, {100, 2, 0ms, 100});
  source.add(1000);
  ASSERT_TRUE(eventually([&] { return source.read_so_far() == 200; }));  // the queue is full
  reader.stop(false);
  ASSERT_TRUE(eventually([&] { return reader.status().ended; }));
  EXPECT_EQ(source.read_so_far(), 200u);
}

TEST(SourceReader, AFailureEndsTheThreadAndKeepsWhatWasRead) {
  CountingSource source;
  source.add(50);
  source.fail_after(50);
  SourceReader reader(source, {100, 4, 0ms, 100});
  ASSERT_TRUE(eventually([&] { return reader.status().ended; }));
  std::vector<std::unique_ptr<ReadResult>> taken;
  reader.take(taken);
  EXPECT_EQ(seqnos(taken).size(), 50u);
  ASSERT_NE(reader.error(), nullptr);
  EXPECT_THROW(std::rethrow_exception(reader.error()), core::Error);
}

TEST(SourceReader, TheConsumerIsWokenByTheFirstEventsAfterATake) {
  CountingSource source;
  SourceReader reader(source, {100, 4, 0ms, 1000});
  pollfd fd{reader.fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&fd, 1, 20), 0);  // nothing yet
  source.add(1);
  EXPECT_EQ(::poll(&fd, 1, 5000), 1);
  const auto status = reader.status();
  EXPECT_EQ(status.events, 1u);
  EXPECT_TRUE(status.first.has_value());
}

TEST(LatencyHistogram, ExactBelow32AndWithin3PercentAbove) {
  LatencyHistogram h;
  EXPECT_EQ(h.quantile(0.5), 0);
  for (std::int64_t v = 1; v <= 31; ++v) h.add(v);
  EXPECT_EQ(h.quantile(0.5), 16);
  EXPECT_EQ(h.quantile(1.0), 31);
  LatencyHistogram big;
  for (std::int64_t v = 1; v <= 100'000; ++v) big.add(v * 1000);  // 1 us .. 100 ms
  EXPECT_EQ(big.count(), 100'000u);
  EXPECT_EQ(big.max(), 100'000'000);
  for (const double q : {0.5, 0.9, 0.99}) {
    const double truth = q * 100'000'000;
    const auto got = static_cast<double>(big.quantile(q));
    EXPECT_GE(got, truth) << q;
    EXPECT_LE(got, truth * (1 + 1.0 / 32)) << q;
  }
  EXPECT_EQ(big.quantile(1.0), 100'000'000);
  LatencyHistogram negative;
  negative.add(-5);  // a clock stepped back
  EXPECT_EQ(negative.quantile(0.5), 0);
}

}  // namespace
}  // namespace m2mlat::capture
