// AgentClient against the in-process agent twin: decoding of every answer, paging, the event
// stream, the bearer token, and failures (refused, dropped, garbage, frozen, not an agent), each
// a core::Error naming the URL.
#include "m2mlat/net/client.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <map>
#include <thread>

#include "../collect/agent_twin.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::net {
namespace {

using testing::AgentTwin;
using testing::Fault;
using testing::TempDir;

// The sessions of the twin, for decoding events.
struct Sessions {
  std::map<std::int64_t, store::Session> by_id;
  explicit Sessions(AgentClient& client) {
    for (auto& s : client.sessions()) by_id[s.id] = s;
  }
  SessionLookup lookup() {
    return [this](std::int64_t id) -> const store::Session* {
      const auto it = by_id.find(id);
      return it == by_id.end() ? nullptr : &it->second;
    };
  }
};

ClientOptions fast() {
  ClientOptions o;
  o.connect_timeout = std::chrono::milliseconds(500);
  o.read_timeout = std::chrono::milliseconds(500);
  return o;
}

// Runs f, which must throw core::Error of `kind` whose message contains every one of `parts`.
template <class F>
void expect_error(F f, core::ErrorKind kind, std::initializer_list<std::string> parts) {
  try {
    f();
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(static_cast<int>(e.kind()), static_cast<int>(kind)) << e.what();
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " lacks " << p;
  }
}

TEST(AgentClient, NormalisesTheUrlAndRefusesOthers) {
  EXPECT_EQ(AgentClient("http://127.0.0.1:8470/").url(), "http://127.0.0.1:8470");
  EXPECT_EQ(AgentClient("https://board-1.local:443").url(), "https://board-1.local:443");
  EXPECT_EQ(AgentClient("http://[::1]:8470").url(), "http://[::1]:8470");
  for (const char* bad :
       {"127.0.0.1:8470", "ftp://h:1", "http://h", "http://h:8470/v1/status", "http://h:99999"})
    expect_error([&] { AgentClient c(bad); }, core::ErrorKind::usage, {bad});
}

TEST(AgentClient, ReadsStatusSessionsEventsSamplesAndLosses) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(5);
  twin.append_clock_sample(-1200);
  twin.append_loss(6, 2);
  AgentClient client(twin.url(), fast());

  const auto st = client.status();
  EXPECT_EQ(st.node, "vehicle");
  EXPECT_EQ(st.role, core::Role::effect);
  EXPECT_EQ(st.store_id, twin.store_id());
  EXPECT_EQ(st.last_seq, 5);
  ASSERT_TRUE(st.clock.has_value());
  EXPECT_EQ(st.clock->offset_ns, -1200);
  EXPECT_EQ(st.lost, 2u);

  Sessions sessions(client);
  ASSERT_EQ(sessions.by_id.size(), 1u);
  EXPECT_EQ(sessions.by_id.begin()->second.label, "twin");

  const auto page = client.events_after(0, 3, sessions.lookup());
  ASSERT_EQ(page.events.size(), 3u);
  EXPECT_EQ(page.last_seq, 5);
  const auto expected = twin.events();
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(page.events[i], expected[i]);
  const auto rest = client.events_after(3, 10000, sessions.lookup());
  ASSERT_EQ(rest.events.size(), 2u);
  EXPECT_EQ(rest.events[1], expected[4]);
  EXPECT_TRUE(client.events_after(5, 10, sessions.lookup()).events.empty());

  const auto samples = client.clock_samples_after(0, 100);
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].sample.offset_ns, -1200);
  EXPECT_TRUE(client.clock_samples_after(samples[0].id, 100).empty());
  const auto losses = client.losses_after(0, 100);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].loss.first_missing, 6u);
  EXPECT_EQ(losses[0].loss.count, 2u);
}

TEST(AgentClient, RefusesAnEventOfAnUnknownSessionAndBadLimits) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(2);
  AgentClient client(twin.url(), fast());
  const SessionLookup none = [](std::int64_t) -> const store::Session* { return nullptr; };
  expect_error([&] { client.events_after(0, 10, none); }, core::ErrorKind::data,
               {twin.url() + "/v1/events?after=0&limit=10 line 1", "session"});
  expect_error([&] { client.events_after(0, 0, none); }, core::ErrorKind::usage, {twin.url()});
  expect_error([&] { client.events_after(0, 10001, none); }, core::ErrorKind::usage, {twin.url()});
}

TEST(AgentClient, StartsAndStopsSessions) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "operator", core::Role::cause);
  AgentClient client(twin.url(), fast());
  const auto begun = client.start_session("run-3", "urban");
  EXPECT_EQ(begun.label, "run-3");
  EXPECT_EQ(begun.node, "operator");
  EXPECT_EQ(begun.id, twin.session());
  const auto ended = client.stop_session();
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->id, begun.id);
  EXPECT_TRUE(ended->end.has_value());
  EXPECT_FALSE(client.stop_session().has_value());  // 409: none open
}

TEST(AgentClient, SendsTheBearerTokenAndReportsARefusal) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.require_token("s3cret");
  expect_error([&] { AgentClient(twin.url(), fast()).status(); }, core::ErrorKind::io,
               {"GET " + twin.url() + "/v1/status", "HTTP 401", "bearer token"});
  auto o = fast();
  o.token = "s3cret";
  EXPECT_EQ(AgentClient(twin.url(), o).status().node, "vehicle");
}

TEST(AgentClient, ReportsARefusedConnectionWithTheUrl) {
  int port = 0;
  {
    httplib::Server probe;  // a port that was free a moment ago and is closed now
    port = probe.bind_to_any_port("127.0.0.1");
  }
  const auto url = "http://127.0.0.1:" + std::to_string(port);
  expect_error([&] { AgentClient(url, fast()).status(); }, core::ErrorKind::io,
               {url + "/v1/status", "connect"});
}

TEST(AgentClient, ReportsADroppedResponse) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(100);
  AgentClient client(twin.url(), fast());
  Sessions sessions(client);
  twin.set_fault(Fault::drop, 1);
  try {
    client.events_after(0, 1000, sessions.lookup());
    FAIL() << "a cut response was taken";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find(twin.url() + "/v1/events"), std::string::npos) << e.what();
  }
  // The next request works again.
  EXPECT_EQ(client.events_after(0, 1000, sessions.lookup()).events.size(), 100u);
}

TEST(AgentClient, ReportsGarbageAndAServerThatIsNoAgent) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(3);
  AgentClient client(twin.url(), fast());
  Sessions sessions(client);
  twin.set_fault(Fault::garbage, 1);
  expect_error([&] { client.events_after(0, 10, sessions.lookup()); }, core::ErrorKind::data,
               {twin.url() + "/v1/events?after=0&limit=10 line 1", "not JSON"});
  twin.set_fault(Fault::no_api_header, 1);
  expect_error([&] { client.status(); }, core::ErrorKind::data, {twin.url() + "/v1/status", "X-M2mlat-Api"});
}

TEST(AgentClient, TimesOutOnAFrozenAgent) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  AgentClient client(twin.url(), fast());
  twin.set_fault(Fault::freeze);
  const auto t0 = std::chrono::steady_clock::now();
  expect_error([&] { client.status(); }, core::ErrorKind::io, {twin.url() + "/v1/status"});
  const auto waited = std::chrono::steady_clock::now() - t0;
  EXPECT_LT(waited, std::chrono::seconds(3));
  twin.set_fault(Fault::none);
}

TEST(AgentClient, StreamsCommittedEventsInOrderUntilAHandlerStops) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(10);
  AgentClient client(twin.url(), fast());
  Sessions sessions(client);
  std::vector<store::StoredEvent> got;
  int chunks = 0;
  // The new events come after the stream's first chunk: started at once, a writer could append all
  // of them before a late stream (a loaded machine) began, and they would come in one chunk.
  std::atomic<bool> first_chunk{false};
  std::thread writer([&] {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(10);  // a safety net
    while (!first_chunk && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    for (int i = 0; i < 5; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      twin.append(3);
    }
  });
  client.stream_events(
      4, sessions.lookup(),
      [&](store::StoredEvent&& e) {
        got.push_back(std::move(e));
        return true;
      },
      [&] {
        ++chunks;
        first_chunk = true;
        return got.size() < 6 + 15;
      });
  writer.join();
  ASSERT_EQ(got.size(), 21u);
  const auto all = twin.events();
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], all[i + 4]);
  EXPECT_GE(chunks, 2);
}

TEST(AgentClient, CancelEndsAStreamFromAnotherThread) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  AgentClient client(twin.url(), fast());
  Sessions sessions(client);
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    client.cancel();
  });
  const auto t0 = std::chrono::steady_clock::now();
  client.stream_events(
      0, sessions.lookup(), [](store::StoredEvent&&) { return true; }, [] { return true; });
  canceller.join();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2));
  // Once cancelled, a stream returns at once; other requests still work.
  client.stream_events(
      0, sessions.lookup(), [](store::StoredEvent&&) { return true; }, [] { return true; });
  EXPECT_EQ(client.status().node, "vehicle");
}

TEST(AgentClient, ReportsAStreamThatBreaksOrFreezes) {
  TempDir dir;
  AgentTwin twin(dir.file("agent.db"), "vehicle", core::Role::effect);
  twin.append(50);
  AgentClient client(twin.url(), fast());
  Sessions sessions(client);
  const auto ignore = [](store::StoredEvent&&) { return true; };
  twin.set_fault(Fault::drop, 1);
  expect_error([&] { client.stream_events(0, sessions.lookup(), ignore, [] { return true; }); },
               core::ErrorKind::io, {twin.url() + "/v1/events/stream?after=0"});
  twin.set_fault(Fault::freeze);
  expect_error([&] { client.stream_events(50, sessions.lookup(), ignore, [] { return true; }); },
               core::ErrorKind::io, {twin.url() + "/v1/events/stream?after=50"});
  twin.set_fault(Fault::none);
}

}  // namespace
}  // namespace m2mlat::net

namespace m2mlat::net {
namespace {

// https:// with the agent's own CA: trusted with --ca-file, refused without it. The certificate is
// made for the test by the openssl command (skipped where it is missing).
TEST(AgentClient, SpeaksTlsAndChecksTheCertificate) {
  TempDir dir;
  const auto cert = dir.file("cert.pem"), key = dir.file("key.pem");
  const auto make =
      "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1 "
      "-addext subjectAltName=IP:127.0.0.1 -keyout " +
      key + " -out " + cert + " >/dev/null 2>&1";
  if (std::system(make.c_str()) != 0) GTEST_SKIP() << "no openssl command to make a certificate";
  httplib::SSLServer server(cert.c_str(), key.c_str());
  ASSERT_TRUE(server.is_valid());
  server.Get("/v1/status", [](const httplib::Request&, httplib::Response& res) {
    Status st;
    st.node = "vehicle";
    st.role = core::Role::effect;
    st.store_id = "0123456789abcdef0123456789abcdef";
    res.set_header(std::string(kApiHeader), "1");
    res.set_content(to_json(st).dump(), "application/json");
  });
  const int port = server.bind_to_any_port("127.0.0.1");
  std::thread thread([&] { server.listen_after_bind(); });
  const auto url = "https://127.0.0.1:" + std::to_string(port);

  auto o = fast();
  o.read_timeout = std::chrono::milliseconds(3000);
  o.ca_file = cert;
  EXPECT_EQ(AgentClient(url, o).status().node, "vehicle");
  o.ca_file.clear();  // the system's CAs do not know this one
  expect_error([&] { AgentClient(url, o).status(); }, core::ErrorKind::io, {url + "/v1/status", "TLS"});
  server.stop();
  thread.join();
}

}  // namespace
}  // namespace m2mlat::net
