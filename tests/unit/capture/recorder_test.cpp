// The recorder loop with the twin and a temporary store: every event stored exactly, bounces
// counted, kernel-visible losses stored with their exact count, limits, and the final drain.
#include "m2mlat/capture/recorder.hpp"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <thread>

#include "m2mlat/capture/fake_gpio.hpp"
#include "m2mlat/capture/gpio_source.hpp"
#include "m2mlat/capture/gyro_channel.hpp"
#include "m2mlat/capture/gyro_source.hpp"
#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/capture/register_twin.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

class RecorderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("m2mlat-recorder-" + std::to_string(::getpid()) + "-" +
              ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db"))
                .string();
    std::filesystem::remove(path_);
    chip_ = gpio_.add_chip("gpio-sim.0-node0", 8);
    spec_.name = "wheel";
    spec_.chip = "gpio-sim.0-node0";
    spec_.line = "3";
  }
  void TearDown() override {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path_ + suffix);
  }
  RecorderOptions options() {
    RecorderOptions o;
    o.session.node = "vehicle";
    o.session.role = core::Role::effect;
    o.session.label = "run-1";
    o.session.scenario = "bench";
    return o;
  }
  // A descriptor that is readable at once: the stop request arrives before the first read.
  struct ReadyFd {
    int fd = ::eventfd(1, EFD_CLOEXEC);
    ~ReadyFd() { ::close(fd); }
  };
  FakeGpio gpio_;
  std::string chip_, path_;
  ChannelSpec spec_;
};

TEST_F(RecorderTest, StopDrainsTheKernelBufferAndEveryTimestampIsStoredUnchanged) {
  auto store = store::Store::open(path_);
  GpioSource source(gpio_, {spec_}, {"vehicle"});
  std::vector<std::int64_t> stamps;
  for (std::int64_t i = 0; i < 300; ++i) {
    stamps.push_back(1762872545000000000 + i * 20'000'017);
    gpio_.edge(chip_, 3, false, static_cast<std::uint64_t>(stamps.back()));
  }
  ReadyFd stop;
  Recorder recorder(store, source, options());
  const auto counters = recorder.run(stop.fd, [] { return std::string("SIGTERM"); });
  EXPECT_EQ(counters.stop_reason, "SIGTERM");
  ASSERT_EQ(counters.channels.size(), 1u);
  EXPECT_EQ(counters.channels[0].events, 300u);
  EXPECT_EQ(counters.channels[0].lost, 0u);
  EXPECT_EQ(counters.last_committed_seq, store.last_seq());
  const auto stored = store.events_after(0, 1000);
  ASSERT_EQ(stored.size(), 300u);
  for (std::size_t i = 0; i < stored.size(); ++i) {
    EXPECT_EQ(stored[i].event.time.ns(), stamps[i]);
    EXPECT_EQ(stored[i].event.seqno, i + 1);
    EXPECT_EQ(stored[i].event.channel, "wheel");
  }
  const auto session = store.session(counters.session_id);
  ASSERT_TRUE(session.has_value());
  EXPECT_TRUE(session->end.has_value());
  EXPECT_EQ(session->node, "vehicle");
  EXPECT_EQ(session->scenario, "bench");
  EXPECT_TRUE(store.losses().empty());
}

TEST_F(RecorderTest, OverflowLossesAreStoredWithTheKernelsCount) {
  auto store = store::Store::open(path_);
  GpioSource source(gpio_, {spec_}, {"vehicle", "m2mlat-", 64});
  for (std::uint64_t i = 1; i <= 200; ++i) gpio_.edge(chip_, 3, false, i * 1'000'000);
  ReadyFd stop;
  Recorder recorder(store, source, options());
  const auto counters = recorder.run(stop.fd);
  EXPECT_EQ(counters.channels[0].events, 64u);
  EXPECT_EQ(counters.channels[0].lost, 136u);
  EXPECT_EQ(counters.channels[0].lost, gpio_.events_dropped());
  const auto losses = store.losses(counters.session_id);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].kind, "seqno_gap");
  EXPECT_EQ(losses[0].channel, "wheel");
  EXPECT_EQ(losses[0].first_missing, 1u);
  EXPECT_EQ(losses[0].count, 136u);
}

TEST_F(RecorderTest, BouncesAreCountedNotStoredAndTheCountLimitStopsExactly) {
  auto store = store::Store::open(path_);
  GpioSource source(gpio_, {spec_}, {"vehicle"});
  // Ten passes 100 ms apart, each with two bounces 1 and 2 ms after the true edge.
  for (std::uint64_t pass = 0; pass < 10; ++pass)
    for (std::uint64_t b = 0; b < 3; ++b) gpio_.edge(chip_, 3, false, pass * 100'000'000 + b * 1'000'000 + 1);
  auto o = options();
  o.refractory["wheel"] = std::chrono::milliseconds(10);
  o.max_events = 7;
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(counters.stop_reason, "count");
  EXPECT_EQ(counters.events, 7u);
  EXPECT_EQ(counters.channels[0].suppressed,
            12u);  // the bounces of the first six passes; the 7th kept edge ends the run
  const auto stored = store.events_after(0, 100);
  ASSERT_EQ(stored.size(), 7u);
  for (std::size_t i = 0; i < stored.size(); ++i)
    EXPECT_EQ(stored[i].event.time.ns(), static_cast<std::int64_t>(i) * 100'000'000 + 1);
}

TEST_F(RecorderTest, TheDurationLimitEndsAnIdleRecording) {
  auto store = store::Store::open(path_);
  GpioSource source(gpio_, {spec_}, {"vehicle"});
  auto o = options();
  o.max_duration = std::chrono::milliseconds(50);
  int progress_calls = 0;
  o.on_progress = [&](const RecordCounters&) { ++progress_calls; };
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(counters.stop_reason, "duration");
  EXPECT_EQ(counters.events, 0u);
  EXPECT_GE(progress_calls, 1);
  EXPECT_TRUE(store.session(counters.session_id)->end.has_value());
}

// A source that delivers one event, then fails as a vanished device would.
class FailingSource final : public Source {
 public:
  void read(ReadResult& out, std::size_t) override {
    if (reads_++ > 0) throw core::Error(core::ErrorKind::io, "device gone");
    core::Event e;
    e.node = "vehicle";
    e.channel = "wheel";
    e.time = core::TimePoint::from_ns(core::Clock::realtime, 42);
    e.seqno = e.line_seqno = 1;
    out.events.push_back(e);
  }
  int fd() const override { return -1; }
  core::Duration poll_interval() const override { return core::Duration{0}; }
  std::vector<std::string> describe() const override { return {"failing"}; }
  std::vector<std::string> channels() const override { return {"wheel"}; }

 private:
  int reads_ = 0;
};

TEST_F(RecorderTest, AFailingSourceKeepsWhatWasReadAndClosesTheSession) {
  auto store = store::Store::open(path_);
  FailingSource source;
  Recorder recorder(store, source, options());
  EXPECT_THROW(recorder.run(-1), core::Error);
  const auto sessions = store.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_TRUE(sessions[0].end.has_value());
  const auto stored = store.events_after(0, 10);
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0].event.time.ns(), 42);
}

// Edges stamped "now" as the test makes them available, read from the recorder's reading thread.
class StreamSource final : public Source {
 public:
  void read(ReadResult& out, std::size_t max_events) override {
    std::lock_guard lock(mutex_);
    for (std::size_t i = 0; i < max_events && next_ <= available_; ++i) {
      auto& e = out.events.emplace_back();
      e.node = "vehicle";
      e.channel = "wheel";
      e.time = core::realtime_now();
      e.seqno = e.line_seqno = next_++;
    }
  }
  int fd() const override { return -1; }
  core::Duration poll_interval() const override { return std::chrono::milliseconds(1); }
  std::vector<std::string> describe() const override { return {"stream"}; }
  std::vector<std::string> channels() const override { return {"wheel"}; }
  void add(std::uint64_t n) {
    std::lock_guard lock(mutex_);
    available_ += n;
  }
  std::uint64_t read_so_far() const {
    std::lock_guard lock(mutex_);
    return next_ - 1;
  }

 private:
  mutable std::mutex mutex_;
  std::uint64_t available_ = 0, next_ = 1;
};

TEST_F(RecorderTest, ReadingGoesOnWhileACommitWaits) {
  // A commit that takes long (an fsync on a slow SD card): while the writing thread is in it, the
  // reading thread keeps draining the source, so that the kernel's buffer does not overflow.
  auto store = store::Store::open(path_);
  StreamSource source;
  source.add(100);
  auto o = options();
  o.commit_interval = std::chrono::milliseconds(1);
  o.max_events = 300;
  bool read_during_commit = false;
  int rounds = 0;
  o.before_commit = [&](std::int64_t, std::vector<store::ClockSample>&) {
    if (rounds++ > 0) return;
    source.add(200);                                         // edges arrive while the first round commits...
    for (int i = 0; i < 5000 && !read_during_commit; ++i) {  // ...and are read meanwhile
      read_during_commit = source.read_so_far() == 300;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_TRUE(read_during_commit);
  EXPECT_EQ(counters.stop_reason, "count");
  EXPECT_EQ(counters.events, 300u);
  EXPECT_EQ(store.events_after(0, 1000).size(), 300u);
  // Every stored event's edge -> durable commit time was measured; the first 100 waited for the
  // slow round.
  EXPECT_EQ(counters.commit_latency.count(), 300u);
  EXPECT_GT(counters.commit_latency.max(), 0);
  EXPECT_LT(counters.commit_latency.max(), 60'000'000'000);
}

// A kernel log replayed from a file: its first edges were stamped an hour before the run, the rest
// as they are read. The old ones are stored but left out of the edge -> durable commit latency (it
// would be their age), and counted as replayed.
class ReplaySource final : public Source {
 public:
  void read(ReadResult& out, std::size_t max_events) override {
    const auto now = core::realtime_now().ns();
    for (std::size_t i = 0; i < max_events && next_ <= 5; ++i) {
      auto& e = out.events.emplace_back();
      e.node = "vehicle";
      e.channel = "wheel";
      e.time = core::TimePoint::from_ns(core::Clock::realtime, next_ <= 3 ? now - 3'600'000'000'000 : now);
      e.seqno = e.line_seqno = next_++;
    }
  }
  int fd() const override { return -1; }
  core::Duration poll_interval() const override { return std::chrono::milliseconds(1); }
  std::vector<std::string> describe() const override { return {"replay"}; }
  std::vector<std::string> channels() const override { return {"wheel"}; }

 private:
  std::uint64_t next_ = 1;
};

TEST_F(RecorderTest, ReplayedEdgesAreLeftOutOfTheCommitLatency) {
  auto store = store::Store::open(path_);
  ReplaySource source;
  auto o = options();
  o.commit_interval = std::chrono::milliseconds(1);
  o.max_events = 5;
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(counters.events, 5u);
  EXPECT_EQ(store.events_after(0, 10).size(), 5u);
  EXPECT_EQ(counters.commit_latency_replayed, 3u);
  EXPECT_EQ(counters.commit_latency.count(), 2u);
  EXPECT_LT(counters.commit_latency.max(), 60'000'000'000);  // not the hour of the replayed ones
}

TEST_F(RecorderTest, TheClockHookHasItsTurnWithoutEdges) {
  // The clock monitor stores the board's clock state while no edge comes, too.
  auto store = store::Store::open(path_);
  StreamSource source;
  auto o = options();
  o.commit_interval = std::chrono::milliseconds(20);
  o.max_duration = std::chrono::milliseconds(300);
  int calls = 0;
  o.before_commit = [&](std::int64_t session, std::vector<store::ClockSample>& samples) {
    if (calls++ > 0) return;
    store::ClockSample sample;
    sample.session_id = session;
    sample.time = core::realtime_now();
    sample.source = "test";
    samples.push_back(sample);
  };
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(counters.events, 0u);
  EXPECT_GE(calls, 5);  // about every 20 ms
  EXPECT_EQ(store.clock_samples(counters.session_id).size(), 1u);
}

TEST_F(RecorderTest, EveryAcknowledgedEventIsInTheStore) {
  auto store = store::Store::open(path_);
  StreamSource source;
  auto o = options();
  o.batch = 100;
  o.commit_interval = std::chrono::milliseconds(50);
  std::vector<std::int64_t> acknowledged;
  o.on_commit = [&](std::int64_t seq) {
    acknowledged.push_back(seq);
    // Every acknowledged event is in the store for any other reader.
    EXPECT_EQ(store.last_seq(), seq);
  };
  o.max_duration = std::chrono::milliseconds(400);
  source.add(250);  // more than two batches at once
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(counters.events, 250u);
  ASSERT_FALSE(acknowledged.empty());
  EXPECT_EQ(acknowledged.back(), 250);
  EXPECT_EQ(store.events_after(0, 1000).size(), 250u);
}

// The gyroscope channel's path as `record --gyro` wires it: the sampler on the register twin, the
// channel's blocks committed every round, and at the stop the sampler stopped first, so every sample
// it read is in the store, in order, under the recorder's session.
TEST_F(RecorderTest, TheRawSampleHookStoresEverySampleTheGyroscopeReadByTheStop) {
  auto store = store::Store::open(path_);
  StreamSource source;
  RegisterTwin twin;
  twin.registers[mpu6050::reg::who_am_i] = 0x68;
  twin.set_rates(100, -200, 300);
  Mpu6050 chip(twin);
  chip.configure({});
  GyroSource gyro(chip, {.period = core::Duration{500'000}});
  GyroChannel channel("wheel_gyro", core::Clock::realtime, mpu6050::kCountsPerDegS, {});
  auto o = options();
  o.commit_interval = std::chrono::milliseconds(20);
  o.max_duration = std::chrono::milliseconds(300);
  int rounds = 0, finals = 0;
  o.raw_samples = [&](const RawRound& round, std::vector<store::RateBlock>& blocks,
                      std::vector<store::Loss>& losses) {
    ++rounds;
    if (round.final) {
      ++finals;
      gyro.stop();
      gyro.join();
    }
    channel.add(gyro.take(), gyro.summary());
    channel.collect(round, core::realtime_now(), blocks, losses);
  };
  gyro.start();
  Recorder recorder(store, source, o);
  const auto counters = recorder.run(-1);
  EXPECT_EQ(finals, 1);
  EXPECT_GE(rounds, 5);  // about every 20 ms, without any edge
  const auto read = gyro.summary().reads;
  EXPECT_GT(read, 100u);
  // The sampler started before the session: what it read before the session began is no session's.
  const auto trace = store.rate_trace(counters.session_id, "wheel_gyro");
  EXPECT_EQ(trace.samples.size(), channel.counters().stored);
  EXPECT_EQ(channel.counters().stored + channel.counters().outside_session, read);
  EXPECT_LT(channel.counters().outside_session, 20u);
  const auto session = store.session(counters.session_id);
  EXPECT_GE(trace.samples.front().time_ns, session->start.ns());
  EXPECT_LE(trace.samples.back().time_ns, session->end->ns());
  for (std::size_t i = 0; i < trace.samples.size(); ++i) {
    EXPECT_EQ(trace.samples[i].raw, (std::array<std::int16_t, 3>{100, -200, 300}));
    if (i > 0) {
      EXPECT_GT(trace.samples[i].time_ns, trace.samples[i - 1].time_ns);
    }
  }
  EXPECT_TRUE(store.session(counters.session_id)->end.has_value());
}

}  // namespace
}  // namespace m2mlat::capture
