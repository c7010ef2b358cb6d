// The API server in process, on an ephemeral loopback port, with a twin backend and a temporary
// store, driven by httplib::Client: every route, the error statuses, the token rule, the SSE stream.
#include "m2mlat/net/server.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <filesystem>
#include <future>
#include <mutex>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"
#include "raw_client.hpp"

namespace m2mlat::net {
namespace {

using nlohmann::json;

// A backend that keeps sessions in the store itself, as the recorder would.
class TwinBackend final : public AgentBackend {
 public:
  explicit TwinBackend(store::Store& store) : store_(store) {}
  Status live_status() override {
    Status s;
    s.node = "vehicle";
    s.role = core::Role::effect;
    s.channels = {{"wheel", 3, 1, 0, 5}};
    s.events = 3;
    s.started_ns = 11;
    return s;
  }
  store::Session begin_session(const SessionRequest& request) override {
    std::lock_guard lock(mutex_);
    end_open();
    store::Session s;
    s.node = "vehicle";
    s.role = core::Role::effect;
    s.label = request.label;
    s.scenario = request.scenario;
    s.start = core::TimePoint::from_ns(core::Clock::realtime, 1000);
    open_ = store_.begin_session(s);
    return *store_.session(*open_);
  }
  std::optional<store::Session> stop_session() override {
    std::lock_guard lock(mutex_);
    return end_open();
  }

 private:
  std::optional<store::Session> end_open() {
    if (!open_) return std::nullopt;
    store_.end_session(*open_, core::TimePoint::from_ns(core::Clock::realtime, 2000));
    auto ended = store_.session(*open_);
    open_.reset();
    return ended;
  }
  store::Store& store_;
  std::mutex mutex_;
  std::optional<std::int64_t> open_;
};

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("m2mlat-server-" + std::to_string(::getpid()) + "-" +
              ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db"))
                .string();
    std::filesystem::remove(path_);
    store_.emplace(store::Store::open(path_));
    backend_.emplace(*store_);
  }
  void TearDown() override {
    server_.reset();
    store_.reset();
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path_ + suffix);
  }
  void start(std::optional<std::string> token = std::nullopt) {
    ServerOptions o;
    o.token = std::move(token);
    start(o);
  }
  void start(ServerOptions o) {
    o.store_path = path_;
    o.port = 0;
    o.ping_interval = std::chrono::milliseconds(200);
    server_ = std::make_unique<AgentServer>(o, *backend_);
    server_->start();
    ASSERT_GT(server_->port(), 0);
  }
  httplib::Client client() {
    httplib::Client c("127.0.0.1", server_->port());
    c.set_read_timeout(5, 0);
    return c;
  }
  // Adds `n` events to a session of the store (opening one if needed); returns their last seq.
  std::int64_t add_events(int n) {
    if (!session_) {
      store::Session s;
      s.node = "vehicle";
      s.role = core::Role::effect;
      s.start = core::TimePoint::from_ns(core::Clock::realtime, 1);
      session_ = store_->begin_session(s);
    }
    std::vector<core::Event> events;
    for (int i = 0; i < n; ++i) {
      core::Event e;
      e.node = "vehicle";
      e.channel = "wheel";
      e.time = core::TimePoint::from_ns(core::Clock::realtime, 1'780'000'000'000'000'000 + next_++ * 1000);
      e.seqno = static_cast<std::uint64_t>(next_);
      e.line_seqno = static_cast<std::uint64_t>(next_);
      events.push_back(e);
    }
    store_->append_events(*session_, events);
    return store_->last_seq();
  }
  static void expect_error(const httplib::Result& r, int status) {
    ASSERT_TRUE(r) << "no response";
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("X-M2mlat-Api"), "1");
    const auto body = json::parse(r->body, nullptr, false);
    ASSERT_FALSE(body.is_discarded()) << r->body;
    EXPECT_EQ(body["error"]["status"], status);
    EXPECT_TRUE(body["error"]["message"].is_string());
  }
  std::vector<json> lines(const std::string& body) {
    std::vector<json> out;
    std::istringstream in(body);
    for (std::string line; std::getline(in, line);) out.push_back(json::parse(line));
    return out;
  }

  std::string path_;
  std::optional<store::Store> store_;
  std::optional<TwinBackend> backend_;
  std::unique_ptr<AgentServer> server_;
  std::optional<std::int64_t> session_;
  std::int64_t next_ = 0;
};

TEST_F(ServerTest, StatusCombinesTheLiveCountersWithTheStore) {
  add_events(4);
  start();
  auto c = client();
  const auto r = c.Get("/v1/status");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("X-M2mlat-Api"), "1");
  const auto status = status_from_json(json::parse(r->body), "status");
  EXPECT_EQ(status.store_id, store_->store_id());
  EXPECT_EQ(status.last_seq, 4);
  EXPECT_EQ(status.node, "vehicle");
  EXPECT_EQ(status.events, 3u);
  EXPECT_GT(status.now_ns, 1'700'000'000'000'000'000);
}

TEST_F(ServerTest, EventsArePagedFromTheStoreInSeqOrder) {
  const auto last = add_events(25);
  start();
  auto c = client();
  auto r = c.Get("/v1/events?after=5&limit=10");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/x-ndjson");
  EXPECT_EQ(r->get_header_value("X-M2mlat-Last-Seq"), std::to_string(last));
  const auto page = lines(r->body);
  ASSERT_EQ(page.size(), 10u);
  const auto stored = store_->events_after(5, 10);
  for (std::size_t i = 0; i < page.size(); ++i)
    EXPECT_EQ(event_from_json(page[i], "t", "vehicle", core::Role::effect), stored[i]);
  r = c.Get("/v1/events");
  EXPECT_EQ(lines(r->body).size(), 25u);
  r = c.Get("/v1/events?after=25");
  EXPECT_EQ(r->status, 200);
  EXPECT_TRUE(r->body.empty());
}

TEST_F(ServerTest, SessionsSamplesAndLosses) {
  add_events(1);
  store::ClockSample sample;
  sample.session_id = *session_;
  sample.time = core::TimePoint::from_ns(core::Clock::realtime, 5);
  sample.source = "chrony";
  store_->append_clock_samples(std::span(&sample, 1));
  store::Loss loss{*session_, "wheel", core::TimePoint::from_ns(core::Clock::realtime, 6), 3, 2, "seqno_gap"};
  store_->append_losses(std::span(&loss, 1));
  start();
  auto c = client();
  auto r = c.Get("/v1/sessions");
  ASSERT_TRUE(r);
  const auto sessions = json::parse(r->body)["sessions"];
  ASSERT_EQ(sessions.size(), 1u);
  EXPECT_EQ(session_from_json(sessions[0], "t"), *store_->session(*session_));
  r = c.Get("/v1/clock-samples?after=0");
  ASSERT_EQ(lines(r->body).size(), 1u);
  EXPECT_EQ(clock_sample_from_json(lines(r->body)[0], "t").sample, sample);
  r = c.Get("/v1/losses");
  ASSERT_EQ(lines(r->body).size(), 1u);
  EXPECT_EQ(loss_from_json(lines(r->body)[0], "t").loss, loss);
  r = c.Get("/v1/losses?after=1");
  EXPECT_TRUE(r->body.empty());
}

// Raw rate blocks resume by id like losses, and a page holds at most kMaxRateBlocksPerPage blocks
// whatever the limit asked.
TEST_F(ServerTest, RateBlocksArePagedByIdAndCapped) {
  add_events(1);
  std::vector<store::RateBlock> blocks;
  for (int i = 0; i < 20; ++i) {
    store::RateBlock b;
    b.session_id = *session_;
    b.channel = "gyro";
    b.first_index = static_cast<std::uint64_t>(i) * 2;
    b.samples = {{1000 + i * 10, 5, {static_cast<std::int16_t>(i), 0, 0}}, {1005 + i * 10, 5, {0, 0, 0}}};
    blocks.push_back(b);
  }
  store_->append_rate_blocks(blocks);
  start();
  auto c = client();
  auto r = c.Get("/v1/rate-blocks?after=0&limit=10000");
  ASSERT_TRUE(r);
  auto page = lines(r->body);
  ASSERT_EQ(page.size(), kMaxRateBlocksPerPage);
  const auto last = rate_block_from_json(page.back(), "t");
  EXPECT_EQ(last.block.first_index, 2 * (kMaxRateBlocksPerPage - 1));
  r = c.Get(fmt::format("/v1/rate-blocks?after={}&limit=3", last.id));
  page = lines(r->body);
  ASSERT_EQ(page.size(), 3u);
  const auto next = rate_block_from_json(page.front(), "t");
  EXPECT_GT(next.id, last.id);
  EXPECT_EQ(next.block.samples.front().raw[0], static_cast<std::int16_t>(kMaxRateBlocksPerPage));
  EXPECT_EQ(next.block.session_id, *session_);
  EXPECT_EQ(c.Get("/v1/rate-blocks?limit=0")->status, 400);
}

TEST_F(ServerTest, SessionControlGoesToTheBackend) {
  start();
  auto c = client();
  expect_error(c.Post("/v1/sessions/current/stop", "", "application/json"), 409);
  auto r = c.Post("/v1/sessions", R"({"label":"run-3","scenario":"urban"})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 201) << r->body;
  const auto begun = session_from_json(json::parse(r->body)["session"], "t");
  EXPECT_EQ(begun.label, "run-3");
  EXPECT_EQ(begun.scenario, "urban");
  EXPECT_FALSE(begun.end.has_value());
  r = c.Post("/v1/sessions/current/stop", "", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  const auto ended = session_from_json(json::parse(r->body)["session"], "t");
  EXPECT_EQ(ended.id, begun.id);
  EXPECT_TRUE(ended.end.has_value());
  expect_error(c.Post("/v1/sessions", R"({"label":5})", "application/json"), 400);
  expect_error(c.Post("/v1/sessions", R"({"labl":"x"})", "application/json"), 400);
  EXPECT_EQ(store_->sessions().size(), 1u);  // the refused requests began nothing
}

TEST_F(ServerTest, MetricsAreServedAsPrometheusText) {
  add_events(2);
  start();
  auto c = client();
  const auto r = c.Get("/metrics");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  EXPECT_NE(r->body.find("m2mlat_last_seq{node=\"vehicle\"} 2\n"), std::string::npos) << r->body;
}

TEST_F(ServerTest, BadRequestsGetTheirStatusAndAJsonError) {
  add_events(3);
  start();
  auto c = client();
  expect_error(c.Get("/v1/nothing"), 404);
  expect_error(c.Get("/"), 404);
  const auto r = c.Delete("/v1/events");
  expect_error(r, 405);
  EXPECT_EQ(r->get_header_value("Allow"), "GET, HEAD");
  expect_error(c.Get("/v1/sessions/current/stop"), 405);
  EXPECT_EQ(c.Get("/v1/sessions/current/stop")->get_header_value("Allow"), "POST");
  expect_error(c.Post("/v1/status", "", "application/json"), 405);
  for (const char* query : {"after=-1", "after=x", "after=99999999999999999999", "limit=0", "limit=10001",
                            "limit=1e3", "after=1&after=2"})
    expect_error(c.Get(std::string("/v1/events?") + query), 400);
  expect_error(c.Get("/v1/losses?limit=100000"), 400);
  expect_error(c.Post("/v1/sessions", std::string(1 << 20, 'x'), "application/json"), 413);
  httplib::Headers many;
  for (int i = 0; i < 100; ++i) many.emplace("X-Filler-" + std::to_string(i), "1");
  expect_error(c.Get("/v1/status", many), 431);
  // Still serving, and nothing was stored by any of it.
  EXPECT_EQ(c.Get("/v1/status")->status, 200);
  EXPECT_EQ(store_->last_seq(), 3);
  EXPECT_EQ(store_->sessions().size(), 1u);
}

TEST_F(ServerTest, ATokenIsRequiredOnEveryRequestWhenSet) {
  const std::string token = "0123456789abcdef0123456789abcdef";
  start(token);
  auto c = client();
  for (const auto& path : {"/v1/status", "/v1/events", "/metrics", "/nothing"}) {
    const auto r = c.Get(path);
    expect_error(r, 401);
    EXPECT_EQ(r->get_header_value("WWW-Authenticate"), "Bearer realm=\"m2mlat\"");
  }
  expect_error(c.Get("/v1/status", {{"Authorization", "Bearer 0123456789abcdef0123456789abcdeX"}}), 401);
  expect_error(c.Get("/v1/status", {{"Authorization", "Basic " + token}}), 401);
  expect_error(
      c.Get("/v1/status", {{"Authorization", "Bearer " + token}, {"Authorization", "Bearer " + token}}), 401);
  expect_error(c.Post("/v1/sessions", "{}", "application/json"), 401);
  EXPECT_TRUE(store_->sessions().empty());
  EXPECT_EQ(c.Get("/v1/status", {{"Authorization", "Bearer " + token}})->status, 200);
  c.set_bearer_token_auth(token.c_str());
  EXPECT_EQ(c.Get("/v1/status")->status, 200);
  expect_error(c.Get("/nothing"), 404);
}

TEST_F(ServerTest, AnAddressOffLoopbackNeedsAToken) {
  ServerOptions o;
  o.store_path = path_;
  o.host = "0.0.0.0";
  EXPECT_THROW(AgentServer(o, *backend_), core::Error);
  o.host = "::";
  EXPECT_THROW(AgentServer(o, *backend_), core::Error);
  o.token = "short";
  EXPECT_THROW(AgentServer(o, *backend_), core::Error);
  o.token = "0123456789abcdef0123456789abcdef";
  EXPECT_NO_THROW(AgentServer(o, *backend_));
  o.tls_cert = "cert.pem";
  EXPECT_THROW(AgentServer(o, *backend_), core::Error);  // a certificate without a key
}

TEST_F(ServerTest, TheStreamSendsCommittedEventsFromTheResumePointAndPingsWhenIdle) {
  add_events(3);
  start();
  auto c = client();
  std::string received;
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    server_->notify_commit(add_events(2));
  });
  // Resume after seq 1 via Last-Event-ID (it wins over after=): events 2..5, then a ping.
  const auto r =
      c.Get("/v1/events/stream?after=0", {{"Last-Event-ID", "1"}}, [&](const char* data, std::size_t n) {
        received.append(data, n);
        return received.find(": ping") == std::string::npos || received.find("id: 5\n") == std::string::npos;
      });
  writer.join();
  EXPECT_NE(received.find("id: 2\nevent: event\ndata: {"), std::string::npos) << received;
  EXPECT_EQ(received.find("id: 1\n"), std::string::npos);
  const auto five = received.find("id: 5\n");
  ASSERT_NE(five, std::string::npos) << received;
  const auto data = received.find("data: ", five) + 6;
  const auto event = event_from_json(json::parse(received.substr(data, received.find('\n', data) - data)),
                                     "sse", "vehicle", core::Role::effect);
  EXPECT_EQ(event, store_->events_after(4, 1).at(0));
  EXPECT_LT(received.find("id: 4\n"), five);
  expect_error(c.Get("/v1/events/stream", {{"Last-Event-ID", "abc"}}), 400);
}

// 50 connections trickling request heads (a byte every 100 ms) hold no worker a valid client
// needs: every one of its requests is answered within 1 s, and the slow ones are closed at the
// request deadline.
TEST_F(ServerTest, SlowConnectionsDoNotDelayValidClientsAndAreCutAtTheDeadline) {
  using namespace std::chrono_literals;
  add_events(3);
  const std::string token = "0123456789abcdef0123456789abcdef";
  ServerOptions o;
  o.token = token;
  o.request_timeout = 2s;
  start(o);
  const auto t0 = std::chrono::steady_clock::now();
  test::SlowLoris loris(server_->port(), 50, 100ms);
  ASSERT_EQ(loris.connected(), 50u);
  for (int i = 0; i < 30; ++i) {
    auto c = client();
    c.set_bearer_token_auth(token.c_str());
    const auto begin = std::chrono::steady_clock::now();
    const auto r = c.Get(i % 2 ? "/v1/status" : "/v1/events?after=1");
    ASSERT_TRUE(r) << i;
    EXPECT_EQ(r->status, 200) << r->body;
    EXPECT_LT(std::chrono::steady_clock::now() - begin, 1s) << i;
  }
  std::this_thread::sleep_until(t0 + 2s);
  EXPECT_EQ(loris.closed_within(1000ms), 50u);
  EXPECT_EQ(server_->counts().timed_out, 50u);
  auto c = client();
  c.set_bearer_token_auth(token.c_str());
  const auto metrics = c.Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_NE(metrics->body.find("m2mlat_http_connections_ended_early_total{node=\"vehicle\",reason=\"timed_out\"} 50\n"),
            std::string::npos)
      << metrics->body;
}

TEST_F(ServerTest, EventStreamsAreLimited) {
  ServerOptions o;
  o.max_streams = 1;
  start(o);
  std::promise<void> open;
  std::atomic<bool> first{true}, done{false};
  auto streaming = std::async(std::launch::async, [&] {
    auto c = client();
    return c.Get("/v1/events/stream", [&](const char*, std::size_t) {
      if (first.exchange(false)) open.set_value();
      return !done.load();
    });
  });
  ASSERT_EQ(open.get_future().wait_for(std::chrono::seconds(5)), std::future_status::ready);
  auto c = client();
  const auto refused = c.Get("/v1/events/stream");
  expect_error(refused, 503);
  EXPECT_NE(refused->body.find("at most 1"), std::string::npos) << refused->body;
  EXPECT_EQ(c.Get("/v1/status")->status, 200);  // other requests are not affected
  done = true;
  streaming.wait();
  // The slot is free again once the server has seen the stream end (at its next write).
  std::string received;
  for (int i = 0; i < 50 && received.find(": ping") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    c.Get("/v1/events/stream", [&](const char* data, std::size_t n) {
      received.append(data, n);
      return false;
    });
  }
  EXPECT_NE(received.find(": ping"), std::string::npos) << received;
}

}  // namespace
}  // namespace m2mlat::net
