// The recorder loop with the twin and a temporary store: every event stored exactly, bounces
// counted, kernel-visible losses stored with their exact count, limits, and the final drain.
#include "m2mlat/capture/recorder.hpp"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <filesystem>

#include "m2mlat/capture/fake_gpio.hpp"
#include "m2mlat/capture/gpio_source.hpp"
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

}  // namespace
}  // namespace m2mlat::capture
