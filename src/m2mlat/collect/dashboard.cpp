// The dashboard's HTTP server and the JSON of its snapshot.
#include "m2mlat/collect/dashboard.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <array>
#include <cmath>
#include <iterator>

#include "m2mlat/collect/web_assets.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/net/auth.hpp"
#include "m2mlat/net/event_stream.hpp"
#include "m2mlat/net/query.hpp"
#include "m2mlat/net/wire.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/stats/bootstrap.hpp"

namespace m2mlat::collect {

namespace {

// A statistic in ms, or null where it is undefined (NaN: no samples).
nlohmann::json ms_or_null(double ms) { return std::isnan(ms) ? nlohmann::json(nullptr) : nlohmann::json(ms); }
nlohmann::json interval_json(const stats::Interval& ms) { return nlohmann::json::array({ms.lower, ms.upper}); }

nlohmann::json sample_json(const LiveSample& s) {
  return {{"t_ns", s.cause_ns}, {"latency_ns", s.latency_ns}, {"ambiguous", s.ambiguous}};
}

// The full loop's figures over the window, or null for a scenario without gyroscope traces.
nlohmann::json loop_json(const std::optional<LiveLoop>& loop) {
  if (!loop) return nullptr;
  nlohmann::json j{{"detector", loop->detector}, {"window_ns", loop->window_ns}, {"chains", loop->chains}};
  constexpr std::array kKeys{"m2m", "g2g", "e2e"};
  for (std::size_t q = 0; q < kKeys.size(); ++q) {
    const auto& x = loop->quantities[q];
    j[kKeys[q]] = {{"n", x.n},
                   {"median_ms", ms_or_null(x.median_ms)},
                   {"p95_ms", ms_or_null(x.p95_ms)},
                   {"last_ns", x.last_ns ? nlohmann::json(*x.last_ns) : nlohmann::json(nullptr)}};
  }
  auto& incomplete = j["incomplete_chains"] = nlohmann::json::object();
  for (const auto& [key, count] : loop->incomplete) incomplete[key] = count;
  j["warnings"] = loop->warnings;
  return j;
}

nlohmann::json summary_json(const LiveSummary& s) {
  const auto& st = s.summary;
  return {{"full_loop", loop_json(s.loop)},
          {"state", to_string(s.state)},
          {"message", s.message},
          {"warnings", s.warnings},
          {"scenario", s.scenario},
          {"cause", s.cause_ref.node.empty() ? "" : core::to_string(s.cause_ref)},
          {"effect", s.effect_ref.node.empty() ? "" : core::to_string(s.effect_ref)},
          {"clock", core::to_string(s.clock)},
          {"cause_events", s.cause_events},
          {"effect_events", s.effect_events},
          {"pairs", s.pairs},
          {"ambiguous", s.ambiguous},
          {"samples", st.n},
          {"cause_unmatched", s.cause_unmatched},
          {"effect_unmatched", s.effect_unmatched},
          {"bounces", s.bounces},
          {"last", s.last ? sample_json(*s.last) : nlohmann::json(nullptr)},
          {"median_ms", ms_or_null(st.median_ms)},
          {"q1_ms", ms_or_null(st.q1_ms)},
          {"q3_ms", ms_or_null(st.q3_ms)},
          {"iqr_ms", ms_or_null(st.iqr_ms)},
          {"median_ci_ms", st.bootstrap ? interval_json(st.bootstrap->median_ms) : nlohmann::json(nullptr)},
          {"iqr_ci_ms", st.bootstrap ? interval_json(st.bootstrap->iqr_ms) : nlohmann::json(nullptr)},
          {"ci_level", st.bootstrap ? nlohmann::json(st.bootstrap->level) : nlohmann::json(nullptr)},
          {"ci_resampled",
           st.bootstrap ? nlohmann::json(report::resampling_name(st.bootstrap->resampling)) : nlohmann::json(nullptr)},
          {"p95_ms", ms_or_null(st.p95_ms)},
          {"mean_ms", ms_or_null(st.mean_ms)},
          {"min_ns", st.min ? nlohmann::json(st.min->ns) : nlohmann::json(nullptr)},
          {"max_ns", st.max ? nlohmann::json(st.max->ns) : nlohmann::json(nullptr)},
          {"store_last_seq", s.store_last_seq},
          {"update_cost_ns", s.update_cost_ns},
          {"pairings", s.pairings},
          // The fields of `stats --json`'s breakdown member (report/breakdown_view.hpp).
          {"breakdown", s.breakdown ? report::breakdown_json(*s.breakdown) : nlohmann::json(nullptr)}};
}

nlohmann::json node_json(const NodeHealth& n) {
  return {{"node", n.node},
          {"url", n.url},
          {"role", core::to_string(n.role)},
          {"state", to_string(n.state)},
          {"last_contact_ns", n.last_contact_ns},
          {"events_per_s", n.events_per_s},
          {"events", n.events},
          {"lost", n.lost},
          {"cursor_seq", n.cursor_seq},
          {"agent_last_seq", n.agent_last_seq},
          {"has_clock", n.has_clock},
          {"clock_offset_ns", n.clock_offset_ns},
          {"clock_max_error_ns", n.clock_max_error_ns},
          {"synchronised", n.synchronised},
          {"last_error", n.last_error}};
}

constexpr const char* kSecurityPolicy =
    "default-src 'none'; script-src 'self'; style-src 'self'; connect-src 'self'; img-src 'self'; "
    "base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

void error_body(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(net::error_body(status, message), "application/json");
}

// Refuses an address off loopback without a token, before anything is bound.
DashboardOptions checked(DashboardOptions o) {
  if (!net::is_loopback(o.host) && o.token.empty())
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("the dashboard on {} (not a loopback address) needs a token: give --token-file "
                    "or set M2MLAT_TOKEN",
                    o.host));
  return o;
}

}  // namespace

nlohmann::json snapshot_json(const LiveSummary& summary, const std::vector<NodeHealth>& nodes,
                             std::int64_t now_ns) {
  nlohmann::json doc{{"format", kLiveFormat}, {"now_ns", now_ns}, {"summary", summary_json(summary)}};
  auto& n = doc["nodes"] = nlohmann::json::array();
  for (const auto& node : nodes) n.push_back(node_json(node));
  auto& r = doc["recent"] = nlohmann::json::array();
  for (const auto& s : summary.recent) r.push_back(sample_json(s));
  auto& h = doc["histogram"];
  h["width_ns"] =
      summary.histogram.empty() ? 0 : summary.histogram.front().upper_ns - summary.histogram.front().lower_ns;
  h["bins"] = nlohmann::json::array();
  for (const auto& b : summary.histogram) h["bins"].push_back({{"lower_ns", b.lower_ns}, {"count", b.count}});
  return doc;
}

void parse_listen_address(std::string_view text, DashboardOptions& options) {
  auto bad = [&](std::string_view why) {
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("--dashboard '{}': {} (expected ADDR:PORT, ADDR or :PORT, e.g. 127.0.0.1:8480 "
                    "or :0 for any free port)",
                    text, why));
  };
  std::string_view host = text, port_text;
  if (!text.empty() && text.front() == '[') {  // [v6]:port or [v6]
    const auto close = text.find(']');
    if (close == std::string_view::npos) bad("no ']' after the IPv6 address");
    host = text.substr(1, close - 1);
    const auto rest = text.substr(close + 1);
    if (!rest.empty() && rest.front() != ':') bad("expected ':' after ']'");
    if (!rest.empty()) port_text = rest.substr(1);
  } else if (const auto colon = text.find(':'); colon != std::string_view::npos) {
    if (text.find(':', colon + 1) != std::string_view::npos) bad("an IPv6 address goes in brackets");
    host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
    if (port_text.empty()) bad("no port after ':'");
  }
  int port = 8480;
  if (!port_text.empty()) {
    if (!core::parse_integer(port_text, port) || port < 0 || port > 65535)
      bad("the port is not a number from 0 to 65535");
  }
  options.host = host.empty() ? "127.0.0.1" : std::string(host);
  options.port = port;
}

Dashboard::Dashboard(DashboardOptions options) : options_(checked(std::move(options))), server_(options_) {
  auto& svr = server_.routes();
  svr.set_default_headers({{"Cache-Control", "no-store"},
                           {"X-Content-Type-Options", "nosniff"},
                           {"Content-Security-Policy", kSecurityPolicy},
                           {"Referrer-Policy", "no-referrer"}});

  const bool need_token = !options_.token.empty();
  svr.set_pre_routing_handler([this, need_token](const httplib::Request& req, httplib::Response& res) {
    using R = httplib::Server::HandlerResponse;
    if (req.method != "GET" && req.method != "HEAD") {
      res.set_header("Allow", "GET, HEAD");
      error_body(res, 405, fmt::format("{} is not allowed: the dashboard only reads", req.method));
      return R::Handled;
    }
    if (!need_token || req.path.rfind("/api/", 0) != 0) return R::Unhandled;
    std::string given;
    const auto auth = req.get_header_value("Authorization");
    if (const auto bearer = net::parse_bearer(auth))
      given = *bearer;
    else if (req.has_param("token"))
      given = req.get_param_value("token");
    if (net::tokens_equal(given, options_.token)) return R::Unhandled;
    res.set_header("WWW-Authenticate", "Bearer realm=\"m2mlat\"");
    error_body(res, 401, "a valid bearer token is required (Authorization header or ?token=)");
    return R::Handled;
  });

  svr.Get("/api/live", [this](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(mutex_);
    res.set_content(snapshot_, "application/json");
  });

  svr.Get("/api/live/stream", [this](const httplib::Request&, httplib::Response& res) {
    std::shared_ptr<net::HttpServer::StreamSlot> slot;
    try {
      slot = net::take_stream_slot(server_);
    } catch (const net::RequestError& e) {
      return error_body(res, e.status(), e.what());
    }
    res.set_header("X-Accel-Buffering", "no");
    // The newest snapshot when it is not the one sent last; `sent` 0: nothing sent yet, so the
    // newest goes out at once. Every publish() notifies, so there is nothing to poll between pings.
    auto next = [this, sent = std::uint64_t{0}](std::string& out) mutable {
      std::lock_guard lock(mutex_);
      if (version_ == 0 || version_ == sent) return;
      fmt::format_to(std::back_inserter(out), "id: {}\nevent: snapshot\ndata: {}\n\n", version_, snapshot_);
      sent = version_;
    };
    net::serve_event_stream(res, std::move(slot), published_,
                            {options_.ping_interval, options_.ping_interval}, std::move(next));
  });

  svr.Get(R"(/[A-Za-z0-9_.-]*)", [](const httplib::Request& req, httplib::Response& res) {
    const auto* asset = find_web_asset(req.path);
    if (!asset) return error_body(res, 404, fmt::format("no such page: {}", req.path));
    res.set_content(asset->bytes.data(), asset->bytes.size(), std::string(asset->content_type));
  });
  server_.start();
}

Dashboard::~Dashboard() { stop(); }

std::string Dashboard::url() const {
  const bool v6 = options_.host.find(':') != std::string::npos;
  return fmt::format("http://{}{}{}:{}/", v6 ? "[" : "", options_.host, v6 ? "]" : "", server_.port());
}

void Dashboard::publish(const nlohmann::json& snapshot) {
  auto text = snapshot.dump();
  {
    std::lock_guard lock(mutex_);
    snapshot_ = std::move(text);
    ++version_;
  }
  published_.notify();
}

void Dashboard::stop() {
  published_.stop();  // the streams end, so that the server's threads can be joined
  server_.stop();
}

}  // namespace m2mlat::collect
