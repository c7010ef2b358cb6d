// The agent in process: a scripted source, a temporary store, the API on an ephemeral port. Events
// are served once committed; sessions begin and end from the API, edges between sessions are counted
// as dropped and not stored; the clock hook's samples land in the open session; a stop ends cleanly.
#include "m2mlat/agent/agent.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <thread>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/net/wire.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::agent {
namespace {

using nlohmann::json;

// Hands over the edges the test pushes (a twin of a live source).
class ScriptedSource final : public capture::Source {
 public:
  void push(int n) {
    std::lock_guard lock(mutex_);
    for (int i = 0; i < n; ++i) {
      core::Event e;
      e.node = "vehicle";
      e.channel = "wheel";
      ++count_;
      e.time =
          core::TimePoint::from_ns(core::Clock::realtime, 1'780'000'000'000'000'000 + count_ * 1'000'000);
      e.seqno = e.line_seqno = static_cast<std::uint64_t>(count_);
      ready_.push_back(e);
    }
  }
  // A clock reading of the source's own (as the simulated rig's daemons give), handed over with
  // the next read.
  void push_clock(std::int64_t offset_ns) {
    std::lock_guard lock(mutex_);
    store::ClockSample s;
    s.time = core::realtime_now();
    s.source = "scripted";
    s.offset_ns = offset_ns;
    s.max_error_ns = 250'000;
    s.synchronised = true;
    clocks_.push_back(s);
  }
  void read(capture::ReadResult& out, std::size_t max_events) override {
    std::lock_guard lock(mutex_);
    while (!ready_.empty() && out.events.size() < max_events) {
      out.events.push_back(ready_.front());
      ready_.erase(ready_.begin());
    }
    for (auto& c : clocks_) out.clock_samples.push_back(c);
    clocks_.clear();
  }
  int fd() const override { return -1; }
  core::Duration poll_interval() const override { return std::chrono::milliseconds(5); }
  std::vector<std::string> describe() const override { return {"wheel: scripted"}; }
  std::vector<std::string> channels() const override { return {"wheel"}; }

 private:
  std::mutex mutex_;
  std::vector<core::Event> ready_;
  std::vector<store::ClockSample> clocks_;
  std::int64_t count_ = 0;
};

class AgentTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() / ("m2mlat-agent-" + std::to_string(::getpid()) + ".db"))
                .string();
    std::filesystem::remove(path_);
  }
  void TearDown() override {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path_ + suffix);
  }
  AgentOptions options() {
    AgentOptions o;
    o.store_path = path_;
    o.recorder.session.node = "vehicle";
    o.recorder.session.role = core::Role::effect;
    o.recorder.session.label = "first";
    o.recorder.commit_interval = std::chrono::milliseconds(10);
    o.recorder.progress_interval = std::chrono::milliseconds(10);
    o.server.port = 0;
    return o;
  }
  // Polls `f` until it holds, up to 5 s.
  template <typename F>
  static bool eventually(F f) {
    for (int i = 0; i < 500; ++i) {
      if (f()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  void stop() {
    const std::uint64_t one = 1;
    ASSERT_EQ(::write(stop_.get(), &one, sizeof one), static_cast<ssize_t>(sizeof one));
  }
  std::string path_;
  core::Fd stop_{::eventfd(0, EFD_CLOEXEC)};
};

net::Status status(httplib::Client& c) {
  const auto r = c.Get("/v1/status");
  EXPECT_TRUE(r);
  return net::status_from_json(json::parse(r->body), "status");
}

TEST_F(AgentTest, SessionsFromTheApiAndDroppedEdgesBetweenThem) {
  ScriptedSource source;
  Agent agent(options(), source);
  agent.start();
  capture::RecordCounters counters;
  std::thread run([&] { counters = agent.run(stop_.get(), [] { return std::string("SIGTERM"); }); });
  httplib::Client c("127.0.0.1", agent.port());

  ASSERT_TRUE(eventually([&] { return status(c).session.has_value(); }));
  EXPECT_EQ(status(c).session->label, "first");
  source.push(5);
  ASSERT_TRUE(eventually([&] { return status(c).last_seq == 5; }));
  ASSERT_TRUE(eventually([&] { return status(c).events == 5; }));

  auto r = c.Post("/v1/sessions", R"({"label":"second","scenario":"urban"})", "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const auto second = net::session_from_json(json::parse(r->body)["session"], "post");
  EXPECT_EQ(second.id, 2);
  EXPECT_EQ(second.scenario, "urban");
  source.push(3);
  ASSERT_TRUE(eventually([&] { return status(c).last_seq == 8; }));

  r = c.Post("/v1/sessions/current/stop", "", "application/json");
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(net::session_from_json(json::parse(r->body)["session"], "stop").id, 2);
  EXPECT_FALSE(status(c).session.has_value());
  EXPECT_EQ(c.Post("/v1/sessions/current/stop", "", "application/json")->status, 409);
  source.push(4);
  ASSERT_TRUE(eventually([&] { return status(c).dropped == 4; }));
  EXPECT_EQ(status(c).last_seq, 8);

  // Every event served is a stored one, in its session.
  r = c.Get("/v1/events?after=0");
  std::istringstream lines(r->body);
  std::vector<std::int64_t> sessions;
  for (std::string line; std::getline(lines, line);)
    sessions.push_back(
        net::event_from_json(json::parse(line), "e", "vehicle", core::Role::effect).session_id);
  EXPECT_EQ(sessions, (std::vector<std::int64_t>{1, 1, 1, 1, 1, 2, 2, 2}));

  stop();
  run.join();
  EXPECT_EQ(counters.stop_reason, "SIGTERM");
  EXPECT_EQ(counters.dropped, 4u);
  store::Options read_only;
  read_only.read_only = true;
  const auto store = store::Store::open(path_, read_only);
  ASSERT_EQ(store.sessions().size(), 2u);
  for (const auto& s : store.sessions()) EXPECT_TRUE(s.end.has_value());
  EXPECT_EQ(store.event_count(), 8);
}

TEST_F(AgentTest, ClockSamplesFromTheHookGoIntoTheOpenSessionAndTheStatus) {
  ScriptedSource source;
  auto o = options();
  o.recorder.before_commit = [](std::int64_t session, std::vector<store::ClockSample>& samples) {
    store::ClockSample s;
    s.session_id = session;
    s.time = core::realtime_now();
    s.source = "test";
    s.offset_ns = -42;
    s.synchronised = true;
    samples.push_back(s);
  };
  Agent agent(o, source);
  agent.start();
  std::thread run([&] { agent.run(stop_.get()); });
  httplib::Client c("127.0.0.1", agent.port());
  ASSERT_TRUE(eventually([&] {
    const auto s = status(c);
    return s.clock.has_value() && s.session.has_value();
  }));
  EXPECT_EQ(status(c).clock->offset_ns, -42);
  ASSERT_TRUE(eventually([&] { return !c.Get("/v1/clock-samples")->body.empty(); }));
  const auto first = json::parse(c.Get("/v1/clock-samples?limit=1")->body);
  EXPECT_EQ(first["session"], 1);
  EXPECT_EQ(first["source"], "test");
  stop();
  run.join();
}

// A simulated board has no clock monitor: its source hands over its own clock readings, which are
// stored and must show in the status as the monitor's would (the coordinator's clock columns).
TEST_F(AgentTest, ClockSamplesFromTheSourceShowInTheStatus) {
  ScriptedSource source;
  Agent agent(options(), source);
  agent.start();
  std::thread run([&] { agent.run(stop_.get()); });
  httplib::Client c("127.0.0.1", agent.port());
  ASSERT_TRUE(eventually([&] { return status(c).session.has_value(); }));
  EXPECT_FALSE(status(c).clock.has_value());
  source.push_clock(1234);
  source.push(1);
  ASSERT_TRUE(eventually([&] { return status(c).clock.has_value(); }));
  EXPECT_EQ(status(c).clock->offset_ns, 1234);
  EXPECT_EQ(status(c).clock->max_error_ns, 250'000);
  EXPECT_TRUE(status(c).clock->synchronised);
  source.push_clock(-77);
  source.push(1);
  ASSERT_TRUE(eventually([&] { return status(c).clock->offset_ns == -77; }));
  const auto stored = json::parse(c.Get("/v1/clock-samples?limit=1")->body);
  EXPECT_EQ(stored["source"], "scripted");
  stop();
  run.join();
}

TEST_F(AgentTest, AnAddressInUseIsRefusedBeforeAnythingIsRecorded) {
  ScriptedSource source;
  Agent first(options(), source);
  first.start();
  auto o = options();
  o.server.port = first.port();
  Agent second(o, source);
  EXPECT_THROW(second.start(), core::Error);
}

}  // namespace
}  // namespace m2mlat::agent
