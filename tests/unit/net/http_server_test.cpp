// The guarded HTTP server on real loopback sockets: slow and idle clients against valid ones, the
// request deadline, the idle timeout, the connection budget (eviction and refusal), the head limit,
// keep-alive, event-stream slots, SO_REUSEPORT left off, and TLS (a stalled handshake is cut, the
// key file's mode is checked).
#include "m2mlat/net/http_server.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>

#include "m2mlat/core/error.hpp"
#include "raw_client.hpp"
#include "temp_dir.hpp"

namespace m2mlat::net {
namespace {

using namespace std::chrono_literals;
using Steady = std::chrono::steady_clock;

// A server with one route, /hello, and the given limits.
std::unique_ptr<HttpServer> hello_server(HttpServerOptions o) {
  auto server = std::make_unique<HttpServer>(std::move(o));
  server->routes().Get("/hello", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("hello", "text/plain");
  });
  server->start();
  return server;
}

// Times `n` valid requests, each on a new connection; returns the slowest (or a failure).
::testing::AssertionResult answered_within(int port, int n, std::chrono::milliseconds limit) {
  for (int i = 0; i < n; ++i) {
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(5s);
    c.set_read_timeout(5s);
    const auto t0 = Steady::now();
    const auto r = c.Get("/hello");
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Steady::now() - t0);
    if (!r) return ::testing::AssertionFailure() << "request " << i << ": no answer (" << r.error() << ")";
    if (r->status != 200 || r->body != "hello")
      return ::testing::AssertionFailure() << "request " << i << ": " << r->status << " " << r->body;
    if (took > limit)
      return ::testing::AssertionFailure() << "request " << i << " took " << took.count() << " ms";
  }
  return ::testing::AssertionSuccess();
}

TEST(HttpServer, SlowClientsAreCutAtTheRequestDeadlineWhileValidOnesAreServed) {
  HttpServerOptions o;
  o.request_timeout = 2s;
  const auto server = hello_server(o);
  const auto t0 = Steady::now();
  // 50 connections trickling a request head, a byte every 100 ms: a per-read timeout never fires.
  test::SlowLoris loris(server->port(), 50, 100ms);
  ASSERT_EQ(loris.connected(), 50u);
  EXPECT_TRUE(answered_within(server->port(), 40, 1000ms));
  // Before the deadline they are all still open (and all have sent something) ...
  std::this_thread::sleep_until(t0 + 1200ms);
  EXPECT_GT(loris.bytes_sent(), 5u);
  EXPECT_EQ(loris.closed_within(0ms), 0u);
  EXPECT_GE(server->counts().open, 50u);
  // ... and all closed soon after it, however the bytes still trickle.
  std::this_thread::sleep_until(t0 + 2000ms);
  EXPECT_EQ(loris.closed_within(1000ms), 50u);
  EXPECT_EQ(server->counts().timed_out, 50u);
  EXPECT_TRUE(answered_within(server->port(), 5, 1000ms));
}

TEST(HttpServer, IdleConnectionsMakeRoomForNewOnes) {
  HttpServerOptions o;   // the default budget: 256 connections
  o.idle_timeout = 30s;  // they would stay for long
  const auto server = hello_server(o);
  std::vector<test::RawClient> idle;
  for (int i = 0; i < 500; ++i) idle.emplace_back(server->port());
  for (const auto& c : idle) ASSERT_TRUE(c.connected());
  // Every one of the 500 was given a thread in turn, the oldest closed to make room.
  for (int i = 0; i < 200 && server->counts().accepted < 500; ++i) std::this_thread::sleep_for(10ms);
  EXPECT_TRUE(answered_within(server->port(), 20, 1000ms));
  const auto counts = server->counts();
  EXPECT_LE(counts.open, 256u);
  EXPECT_GE(counts.evicted, 500u - 256u);
  EXPECT_EQ(counts.refused, 0u);
  // The oldest were the ones closed; the newest are still open.
  EXPECT_TRUE(idle.front().closed_within(1000ms));
  EXPECT_FALSE(idle.back().closed_within(0ms));
}

TEST(HttpServer, AnIdleConnectionIsClosedAfterTheIdleTimeout) {
  HttpServerOptions o;
  o.idle_timeout = 300ms;
  const auto server = hello_server(o);
  test::RawClient quiet(server->port());
  ASSERT_TRUE(quiet.connected());
  const auto t0 = Steady::now();
  EXPECT_TRUE(quiet.closed_within(2000ms));
  EXPECT_GE(Steady::now() - t0, 250ms);
  EXPECT_EQ(server->counts().idle, 1u);
}

TEST(HttpServer, KeepAliveServesManyRequestsOnOneConnection) {
  const auto server = hello_server({});
  httplib::Client c("127.0.0.1", server->port());
  c.set_keep_alive(true);
  for (int i = 0; i < 5; ++i) {
    const auto r = c.Get("/hello");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->body, "hello");
  }
  EXPECT_EQ(server->counts().accepted, 1u);
  // Two requests in one write (pipelined) get two answers.
  test::RawClient raw(server->port());
  ASSERT_TRUE(raw.send(
      "GET /hello HTTP/1.1\r\nHost: x\r\n\r\nGET /hello HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
  const auto got = raw.read_until_closed(2000ms);
  EXPECT_EQ(got.find("HTTP/1.1 200"), 0u) << got;
  EXPECT_NE(got.find("HTTP/1.1 200", 1), std::string::npos) << got;
}

TEST(HttpServer, WhenEveryConnectionIsServingANewOneGets503AtOnce) {
  HttpServerOptions o;
  o.max_connections = 2;
  auto server = std::make_unique<HttpServer>(o);
  std::mutex mutex;
  std::condition_variable cv;
  int inside = 0;
  bool release = false;
  server->routes().Get("/wait", [&](const httplib::Request&, httplib::Response& res) {
    std::unique_lock lock(mutex);
    ++inside;
    cv.notify_all();
    cv.wait(lock, [&] { return release; });
    res.set_content("done", "text/plain");
  });
  server->start();
  std::vector<std::future<int>> busy;
  for (int i = 0; i < 2; ++i)
    busy.push_back(std::async(std::launch::async, [&] {
      httplib::Client c("127.0.0.1", server->port());
      const auto r = c.Get("/wait");
      return r ? r->status : -1;
    }));
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, 5s, [&] { return inside == 2; }));
  }
  test::RawClient third(server->port());
  const auto t0 = Steady::now();
  const auto answer = third.read_until_closed(2000ms);
  EXPECT_LT(Steady::now() - t0, 500ms);
  EXPECT_EQ(answer.rfind("HTTP/1.1 503", 0), 0u) << answer;
  EXPECT_NE(answer.find("\"status\":503"), std::string::npos) << answer;
  EXPECT_EQ(server->counts().refused, 1u);
  {
    std::lock_guard lock(mutex);
    release = true;
  }
  cv.notify_all();
  for (auto& f : busy) EXPECT_EQ(f.get(), 200);
  httplib::Client c("127.0.0.1", server->port());
  c.set_keep_alive(false);
  const auto r = c.Get("/wait");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
}

TEST(HttpServer, AnOverlongRequestHeadIsRefused) {
  HttpServerOptions o;
  o.max_head = 2048;
  const auto server = hello_server(o);
  httplib::Client c("127.0.0.1", server->port());
  auto r = c.Get("/hello", {{"X-Filler", std::string(1000, 'x')}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  r = c.Get("/hello", {{"X-Filler", std::string(1000, 'x')}, {"X-Filler-2", std::string(1500, 'x')}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("\"status\":400"), std::string::npos) << r->body;
}

TEST(HttpServer, EventStreamsHaveTheirOwnLimit) {
  HttpServerOptions o;
  o.max_streams = 2;
  HttpServer server(o);
  auto a = server.stream_slot();
  auto b = server.stream_slot();
  EXPECT_TRUE(a && b);
  EXPECT_EQ(server.stream_slot(), nullptr);
  a.reset();
  EXPECT_NE(server.stream_slot(), nullptr);
}

TEST(HttpServer, NoOtherSocketCanShareThePort) {
  const auto try_bind = [](int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEPORT, &yes, sizeof yes);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool bound = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    return bound;
  };
  const auto server = hello_server({});
  EXPECT_FALSE(try_bind(server->port()));
  EXPECT_TRUE(answered_within(server->port(), 1, 1000ms));
  // The check is real: httplib's own default (SO_REUSEPORT on) lets the same socket in.
  httplib::Server plain;
  const int port = plain.bind_to_any_port("127.0.0.1");
  ASSERT_GT(port, 0);
  EXPECT_TRUE(try_bind(port));
}

// A temporary folder with a self-signed certificate and its key (mode 0600), made by the openssl
// command (the test is skipped where it is missing).
struct TlsFiles {
  m2mlat::testing::TempDir temp;
  const std::filesystem::path& dir = temp.path();
  std::string cert = (dir / "cert.pem").string(), key = (dir / "key.pem").string();
  bool made = false;
  TlsFiles() {
    const auto command =
        "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1 "
        "-addext subjectAltName=IP:127.0.0.1 -keyout " +
        key + " -out " + cert + " >/dev/null 2>&1";
    made = std::system(command.c_str()) == 0 && ::chmod(key.c_str(), 0600) == 0;
  }
};

TEST(HttpServer, TlsServesAndCutsAStalledHandshake) {
  TlsFiles files;
  if (!files.made) GTEST_SKIP() << "no openssl command to make a certificate";
  HttpServerOptions o;
  o.tls_cert = files.cert;
  o.tls_key = files.key;
  o.request_timeout = 1s;
  const auto server = hello_server(o);
  EXPECT_TRUE(server->tls());
  // A client that begins a TLS record and stops.
  test::RawClient stalled(server->port());
  ASSERT_TRUE(stalled.send(std::string_view("\x16\x03\x01", 3)));
  const auto t0 = Steady::now();
  for (int i = 0; i < 10; ++i) {
    httplib::SSLClient c("127.0.0.1", server->port());
    c.set_ca_cert_path(files.cert.c_str());
    c.enable_server_certificate_verification(true);
    const auto r = c.Get("/hello");
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ(r->body, "hello");
  }
  EXPECT_TRUE(stalled.closed_within(2000ms));
  EXPECT_GE(Steady::now() - t0, 900ms);
  EXPECT_EQ(server->counts().timed_out, 1u);
}

TEST(HttpServer, ATlsKeyOthersCanReadIsRefused) {
  TlsFiles files;
  if (!files.made) GTEST_SKIP() << "no openssl command to make a certificate";
  HttpServerOptions o;
  o.tls_cert = files.cert;
  o.tls_key = files.key;
  ASSERT_EQ(::chmod(files.key.c_str(), 0644), 0);
  try {
    HttpServer server(o);
    FAIL() << "a world-readable key was accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("chmod 600 " + files.key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0644"), std::string::npos) << e.what();
  }
  ASSERT_EQ(::chmod(files.key.c_str(), 0660), 0);
  EXPECT_THROW(HttpServer{o}, core::Error);
  ASSERT_EQ(::chmod(files.key.c_str(), 0400), 0);
  EXPECT_NO_THROW(HttpServer{o});
  o.tls_key = files.cert;  // not a key at all (and the mode of a certificate)
  ::chmod(files.cert.c_str(), 0600);
  EXPECT_THROW(HttpServer{o}, core::Error);
}

}  // namespace
}  // namespace m2mlat::net
