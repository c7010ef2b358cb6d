// The dashboard: its snapshot JSON, the embedded page served with the right content types, the
// event stream, the access rule, and the live view feeding it from a simulated campaign store.
#include "m2mlat/collect/dashboard.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <future>
#include <thread>

#include "../net/raw_client.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/collect/live_view.hpp"
#include "m2mlat/collect/web_assets.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

using namespace m2mlat;

namespace {

constexpr std::int64_t kNow = 1'780'304'400'000'000'000;

collect::DashboardOptions ephemeral() {
  collect::DashboardOptions o;
  o.port = 0;
  return o;
}

httplib::Client client_of(const collect::Dashboard& d) {
  httplib::Client c("127.0.0.1", d.port());
  c.set_read_timeout(std::chrono::seconds(5));
  return c;
}

collect::LiveSummary small_summary() {
  collect::LiveSummary s;
  s.state = collect::LiveState::ok;
  s.scenario = "bench";
  s.cause_ref = {"operator", "wheel"};
  s.effect_ref = {"vehicle", "wheel"};
  s.pairs = 2;
  s.summary.n = 2;
  s.summary.median_ms = 850.5;
  s.recent = {{kNow - 3'000'000'000, 800'000'000, false}, {kNow - 1'000'000'000, 901'000'000, true}};
  s.last = s.recent.back();
  s.histogram = {{800'000'000, 900'000'000, 1}, {900'000'000, 1'000'000'000, 1}};
  return s;
}

}  // namespace

TEST(Dashboard, SnapshotJson) {
  collect::NodeHealth n;
  n.node = "vehicle";
  n.url = "http://127.0.0.1:1";
  n.role = core::Role::effect;
  n.state = collect::NodeState::stale;
  n.lost = 3;
  n.has_clock = true;
  n.clock_max_error_ns = 250'000;
  const auto j = collect::snapshot_json(small_summary(), {n}, kNow);
  EXPECT_EQ(j["format"], "m2mlat-live/1");
  EXPECT_EQ(j["now_ns"], kNow);
  const auto& s = j["summary"];
  EXPECT_EQ(s["state"], "ok");
  EXPECT_EQ(s["cause"], "operator/wheel");
  EXPECT_EQ(s["samples"], 2);
  EXPECT_EQ(s["median_ms"], 850.5);
  EXPECT_TRUE(s["iqr_ms"].is_null());  // NaN: not a JSON number
  EXPECT_EQ(s["last"]["latency_ns"], 901'000'000);
  EXPECT_EQ(s["last"]["ambiguous"], true);
  ASSERT_EQ(j["recent"].size(), 2u);
  EXPECT_EQ(j["recent"][0]["t_ns"], kNow - 3'000'000'000);
  EXPECT_EQ(j["histogram"]["width_ns"], 100'000'000);
  EXPECT_EQ(j["histogram"]["bins"][1]["lower_ns"], 900'000'000);
  ASSERT_EQ(j["nodes"].size(), 1u);
  EXPECT_EQ(j["nodes"][0]["state"], "stale");
  EXPECT_EQ(j["nodes"][0]["role"], "effect");
  EXPECT_EQ(j["nodes"][0]["lost"], 3);
  EXPECT_EQ(j["nodes"][0]["clock_max_error_ns"], 250'000);
  // Before any pairing: empty lists, nulls, never NaN.
  const auto fresh = collect::snapshot_json({}, {}, kNow);
  EXPECT_EQ(fresh["summary"]["state"], "waiting");
  EXPECT_TRUE(fresh["summary"]["median_ms"].is_null());
  EXPECT_TRUE(fresh["summary"]["last"].is_null());
  EXPECT_EQ(fresh["histogram"]["width_ns"], 0);
  EXPECT_TRUE(fresh["recent"].empty());
}

TEST(Dashboard, ServesEveryEmbeddedAssetWithItsContentType) {
  ASSERT_GE(collect::web_assets().size(), 3u);
  collect::Dashboard d(ephemeral());
  EXPECT_EQ(d.url(), "http://127.0.0.1:" + std::to_string(d.port()) + "/");
  auto c = client_of(d);
  for (const auto& asset : collect::web_assets()) {
    auto res = c.Get(std::string(asset.path));
    ASSERT_TRUE(res) << asset.path;
    EXPECT_EQ(res->status, 200) << asset.path;
    EXPECT_EQ(res->get_header_value("Content-Type"), asset.content_type) << asset.path;
    EXPECT_EQ(res->body, asset.bytes) << asset.path;
    EXPECT_EQ(res->get_header_value("Cache-Control"), "no-store");
    EXPECT_NE(res->get_header_value("Content-Security-Policy").find("default-src 'none'"), std::string::npos);
  }
  const auto types = [&](std::string_view path) {
    return std::string(collect::find_web_asset(path)->content_type);
  };
  EXPECT_EQ(types("/dashboard.html"), "text/html; charset=utf-8");
  EXPECT_EQ(types("/dashboard.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(types("/dashboard.css"), "text/css; charset=utf-8");
  // The page references only embedded files.
  const auto page = std::string(collect::find_web_asset("/")->bytes);
  for (const char* ref : {"dashboard.js", "dashboard.css", "favicon.svg"}) {
    EXPECT_NE(page.find(ref), std::string::npos) << ref;
    EXPECT_NE(collect::find_web_asset(std::string("/") + ref), nullptr) << ref;
  }
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);

  auto root = c.Get("/");
  ASSERT_TRUE(root);
  EXPECT_EQ(root->status, 200);
  EXPECT_EQ(root->body, page);
  auto missing = c.Get("/nothing.js");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(nlohmann::json::parse(missing->body)["error"]["status"], 404);
  auto post = c.Post("/api/live", "{}", "application/json");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 405);
  EXPECT_EQ(post->get_header_value("Allow"), "GET, HEAD");
}

TEST(Dashboard, LiveJsonAndStream) {
  collect::Dashboard d(ephemeral());
  auto c = client_of(d);
  auto before = c.Get("/api/live");
  ASSERT_TRUE(before);
  EXPECT_EQ(before->status, 200);
  EXPECT_EQ(before->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(before->body, "{}");

  const auto first = collect::snapshot_json(small_summary(), {}, kNow);
  d.publish(first);
  auto after = c.Get("/api/live");
  ASSERT_TRUE(after);
  EXPECT_EQ(nlohmann::json::parse(after->body), first);

  // The stream sends the newest snapshot at once, then each one published.
  std::promise<void> got_first;
  std::atomic<int> events{0};
  std::string received;
  std::string content_type;
  auto streaming = std::async(std::launch::async, [&] {
    auto sc = client_of(d);
    return sc.Get(
        "/api/live/stream",
        [&](const httplib::Response& r) {
          content_type = r.get_header_value("Content-Type");
          return true;
        },
        [&](const char* data, std::size_t size) {
          received.append(data, size);
          const auto n = [&] {
            int k = 0;
            for (auto at = received.find("event: snapshot\n"); at != std::string::npos;
                 at = received.find("event: snapshot\n", at + 1))
              ++k;
            return k;
          }();
          if (n >= 1 && events.load() == 0) got_first.set_value();
          events = n;
          return n < 2;  // done after the second snapshot
        });
  });
  ASSERT_EQ(got_first.get_future().wait_for(std::chrono::seconds(5)), std::future_status::ready);
  auto second = first;
  second["now_ns"] = kNow + 250'000'000;
  d.publish(second);
  ASSERT_EQ(streaming.wait_for(std::chrono::seconds(5)), std::future_status::ready);
  streaming.get();
  EXPECT_EQ(content_type, "text/event-stream");
  EXPECT_EQ(events.load(), 2);
  EXPECT_NE(received.find("id: 1\nevent: snapshot\ndata: " + first.dump() + "\n\n"), std::string::npos);
  EXPECT_NE(received.find("id: 2\nevent: snapshot\ndata: " + second.dump() + "\n\n"), std::string::npos);
}

TEST(Dashboard, StopEndsOpenStreams) {
  auto d = std::make_unique<collect::Dashboard>(ephemeral());
  d->publish(collect::snapshot_json({}, {}, kNow));
  std::promise<void> connected;
  std::atomic<bool> signalled{false};
  auto streaming = std::async(std::launch::async, [&] {
    auto sc = client_of(*d);
    sc.Get("/api/live/stream", [&](const char*, std::size_t) {
      if (!signalled.exchange(true)) connected.set_value();
      return true;
    });
  });
  ASSERT_EQ(connected.get_future().wait_for(std::chrono::seconds(5)), std::future_status::ready);
  const auto t0 = std::chrono::steady_clock::now();
  d->stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(3));
  EXPECT_EQ(streaming.wait_for(std::chrono::seconds(5)), std::future_status::ready);
}

TEST(Dashboard, TokenRule) {
  // Off loopback a token is required before anything listens.
  collect::DashboardOptions open = ephemeral();
  open.host = "0.0.0.0";
  try {
    collect::Dashboard d(open);
    FAIL() << "started on 0.0.0.0 without a token";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("token"), std::string::npos);
  }
  // With a token, /api/* needs it (header or query); the page itself does not.
  auto o = ephemeral();
  o.token = "0123456789abcdef-token";
  collect::Dashboard d(o);
  auto c = client_of(d);
  auto denied = c.Get("/api/live");
  ASSERT_TRUE(denied);
  EXPECT_EQ(denied->status, 401);
  EXPECT_NE(denied->get_header_value("WWW-Authenticate").find("Bearer"), std::string::npos);
  auto wrong = c.Get("/api/live", {{"Authorization", "Bearer 0123456789abcdef-toke"}});
  ASSERT_TRUE(wrong);
  EXPECT_EQ(wrong->status, 401);
  auto header = c.Get("/api/live", {{"Authorization", "Bearer 0123456789abcdef-token"}});
  ASSERT_TRUE(header);
  EXPECT_EQ(header->status, 200);
  auto query = c.Get("/api/live?token=0123456789abcdef-token");
  ASSERT_TRUE(query);
  EXPECT_EQ(query->status, 200);
  auto stream = c.Get("/api/live/stream");
  ASSERT_TRUE(stream);
  EXPECT_EQ(stream->status, 401);
  auto page = c.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
}

// 50 connections trickling request heads (a byte every 100 ms) do not delay the page's data: every
// /api/live is answered within 1 s, and the slow ones are closed at the request deadline.
TEST(Dashboard, SlowConnectionsDoNotDelayValidClients) {
  using namespace std::chrono_literals;
  auto o = ephemeral();
  o.request_timeout = 2s;
  collect::Dashboard d(o);
  d.publish(collect::snapshot_json(small_summary(), {}, kNow));
  const auto t0 = std::chrono::steady_clock::now();
  test::SlowLoris loris(d.port(), 50, 100ms);
  ASSERT_EQ(loris.connected(), 50u);
  for (int i = 0; i < 30; ++i) {
    auto c = client_of(d);
    const auto begin = std::chrono::steady_clock::now();
    const auto r = c.Get("/api/live");
    ASSERT_TRUE(r) << i;
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(nlohmann::json::parse(r->body)["summary"]["scenario"], "bench");
    EXPECT_LT(std::chrono::steady_clock::now() - begin, 1s) << i;
  }
  std::this_thread::sleep_until(t0 + 2s);
  EXPECT_EQ(loris.closed_within(1000ms), 50u);
  EXPECT_EQ(d.counts().timed_out, 50u);
}

TEST(Dashboard, ParsesListenAddresses) {
  collect::DashboardOptions o;
  collect::parse_listen_address("127.0.0.1:8480", o);
  EXPECT_EQ(o.host, "127.0.0.1");
  EXPECT_EQ(o.port, 8480);
  collect::parse_listen_address(":0", o);
  EXPECT_EQ(o.host, "127.0.0.1");
  EXPECT_EQ(o.port, 0);
  collect::parse_listen_address("0.0.0.0", o);
  EXPECT_EQ(o.host, "0.0.0.0");
  EXPECT_EQ(o.port, 8480);
  collect::parse_listen_address("[::1]:9000", o);
  EXPECT_EQ(o.host, "::1");
  EXPECT_EQ(o.port, 9000);
  for (const char* bad : {"127.0.0.1:", "127.0.0.1:x", "127.0.0.1:70000", "::1:80", "[::1", "[::1]x"})
    EXPECT_THROW(collect::parse_listen_address(bad, o), core::Error) << bad;
}

// The live view pairs a simulated campaign store and serves the result: the numbers on the page
// are the pairing's.
TEST(Dashboard, LiveViewServesThePairing) {
  const m2mlat::testing::TempDir dir;
  const auto path = dir.file("campaign.db");
  {
    auto store = store::Store::open(path);
    auto config = sim::preset("static_wifi");
    config.manoeuvres = 40;
    capture::record_simulation(store, config, "live");
  }
  collect::LiveViewOptions o;
  o.store_path = path;
  o.dashboard = ephemeral();
  o.terminal = false;
  o.min_period = std::chrono::milliseconds(20);
  {
    collect::LiveView view(o);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (view.summary().state != collect::LiveState::ok && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_EQ(view.summary().state, collect::LiveState::ok) << view.summary().message;
    collect::NodeHealth n;
    n.node = "operator";
    view.refresh({n}, kNow);
    httplib::Client c("127.0.0.1",
                      std::stoi(view.dashboard_url().substr(view.dashboard_url().rfind(':') + 1)));
    auto res = c.Get("/api/live");
    ASSERT_TRUE(res);
    const auto j = nlohmann::json::parse(res->body);
    EXPECT_EQ(j["summary"]["samples"], view.summary().summary.n);
    EXPECT_GT(j["summary"]["samples"].get<int>(), 30);
    EXPECT_EQ(j["summary"]["scenario"], "static_wifi");
    EXPECT_EQ(j["nodes"][0]["node"], "operator");
    const auto final_summary = view.finish({n}, kNow);
    EXPECT_EQ(final_summary.summary.n, view.summary().summary.n);
  }
}
