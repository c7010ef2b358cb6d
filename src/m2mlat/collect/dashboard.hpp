// The coordinator's web dashboard: an HTTP server (cpp-httplib) that serves the embedded page
// (web/, see web_assets.hpp), the live snapshot as JSON and the same snapshot as a server-sent event
// stream, so that a browser follows a measurement without reloading.
//
//   GET /                  the page (dashboard.html); /dashboard.js, /dashboard.css likewise
//   GET /api/live          the newest snapshot, application/json (format m2mlat-live/1 below)
//   GET /api/live/stream   text/event-stream: `id: N\nevent: snapshot\ndata: <snapshot>\n\n` for every
//                          published snapshot (the newest at once on connecting); `: ping` every 15 s
//                          when nothing is published
//
// Access rule (as the agent's, net/auth.hpp): on a loopback address no token is needed; on any other
// address the server refuses to start without one, and then /api/* must carry it, as
// `Authorization: Bearer <token>` or, because a browser's EventSource cannot send headers, as the
// query parameter `token=<token>` (the page passes on the token of its own URL). The static page
// holds no data and is served to anyone. Every response says Cache-Control: no-store and carries a
// Content-Security-Policy that allows only this origin (no inline script, nothing from elsewhere).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "m2mlat/collect/health.hpp"
#include "m2mlat/collect/live_pairing.hpp"
#include "m2mlat/net/event_stream.hpp"
#include "m2mlat/net/http_server.hpp"

namespace m2mlat::collect {

inline constexpr std::string_view kLiveFormat = "m2mlat-live/1";

// The snapshot the page shows, format m2mlat-live/1 (docs/dashboard.md lists every field):
// {"format","now_ns","summary":{state, message, scenario, cause, effect, clock, counts, last,
// median_ms, q1_ms, q3_ms, iqr_ms, p95_ms, mean_ms, min_ns, max_ns, ...},"nodes":[...],
// "recent":[{"t_ns","latency_ns","ambiguous"}],"histogram":{"width_ns","bins":[{"lower_ns","count"}]}}.
// Times are int64 ns; statistics in ms are null when undefined (no samples).
nlohmann::json snapshot_json(const LiveSummary& summary, const std::vector<NodeHealth>& nodes,
                             std::int64_t now_ns);

// Where to listen and the connection limits are the HttpServer's (net/http_server.hpp): port 8480
// (0: an ephemeral port, see Dashboard::port()), at most 8 event streams (503 beyond), no TLS.
struct DashboardOptions : net::HttpServerOptions {
  DashboardOptions() {
    port = 8480;
    max_streams = 8;
    max_body = 0;  // the dashboard only reads
    what = "the dashboard";
  }
  std::string token;  // required (non-empty) unless host is loopback
  std::chrono::seconds ping_interval{15};
};

// Parses --dashboard ADDR:PORT into host and port: "127.0.0.1:8480", "0.0.0.0" (port 8480),
// ":0" (127.0.0.1, an ephemeral port), "[::1]:8480". Throws core::Error(usage) naming the flag.
void parse_listen_address(std::string_view text, DashboardOptions& options);

class Dashboard {
 public:
  // Binds and starts serving in its own threads. Throws core::Error: usage for a non-loopback
  // address without a token; io if the address cannot be bound.
  explicit Dashboard(DashboardOptions options);
  ~Dashboard();  // stops
  Dashboard(const Dashboard&) = delete;
  Dashboard& operator=(const Dashboard&) = delete;

  int port() const { return server_.port(); }
  std::string url() const;  // "http://127.0.0.1:8480/" (the bound port)
  net::ConnectionCounts counts() const { return server_.counts(); }

  // Replaces the snapshot served and pushes it to every open stream.
  void publish(const nlohmann::json& snapshot);
  // Stops accepting, ends the streams, joins the server thread. Idempotent.
  void stop();

 private:
  DashboardOptions options_;
  net::HttpServer server_;

  std::mutex mutex_;
  std::string snapshot_ = "{}";  // serialised
  std::uint64_t version_ = 0;    // publish() count
  net::StreamSignal published_;  // publish() wakes the event streams
};

}  // namespace m2mlat::collect
