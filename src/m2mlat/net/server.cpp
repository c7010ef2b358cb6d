// Routes, the pre-routing gate, the event stream's source, and the leased read-only stores.
#include "m2mlat/net/server.hpp"

#include <fmt/format.h>
#include <httplib.h>
#include <time.h>

#include <array>
#include <iterator>
#include <map>
#include <type_traits>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/version.hpp"
#include "m2mlat/net/auth.hpp"
#include "m2mlat/net/event_stream.hpp"
#include "m2mlat/net/metrics.hpp"
#include "m2mlat/net/reader_pool.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::net {

namespace {

constexpr const char* kJson = "application/json";
constexpr const char* kNdjson = "application/x-ndjson";
// A POST body up to this many times the limit is read and discarded before the 413 (see gate()).
constexpr std::uint64_t kDrainFactor = 64;

// The API's paths and the methods each takes (HEAD goes with GET).
struct Route {
  std::string_view path;
  bool get;
  bool post;
};
constexpr std::array kRoutes{
    Route{"/v1/status", true, false},
    Route{"/v1/events", true, false},
    Route{"/v1/events/stream", true, false},
    Route{"/v1/sessions", true, true},
    Route{"/v1/sessions/current/stop", false, true},
    Route{"/v1/clock-samples", true, false},
    Route{"/v1/losses", true, false},
    Route{"/v1/rate-blocks", true, false},
    Route{"/v1/markers", true, false},
    Route{"/metrics", true, false},
};

void fail(httplib::Response& res, int status, std::string_view message) {
  res.status = status;
  res.set_content(error_body(status, message), kJson);
}

std::optional<std::string_view> param(const httplib::Request& req, const char* name) {
  const auto count = req.get_param_value_count(name);
  if (count == 0) return std::nullopt;
  if (count > 1) throw RequestError(400, fmt::format("{} given {} times", name, count));
  const auto it = req.params.find(name);
  return std::string_view(it->second);
}

template <typename Items>
std::string ndjson(const Items& items) {
  std::string out;
  for (const auto& item : items) {
    if constexpr (std::is_same_v<typename Items::value_type, store::StoredEvent>)
      append_json(out, item);  // the hot path of a catch-up
    else
      out += to_json(item).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    out += '\n';
  }
  return out;
}

// Refuses an address off loopback without a token, before anything is bound or loaded.
ServerOptions checked(ServerOptions o) {
  if (o.host.size() >= 2 && o.host.front() == '[' && o.host.back() == ']')
    o.host = o.host.substr(1, o.host.size() - 2);
  if (o.token) check_token(*o.token, "the token");
  if (!o.token && !is_loopback(o.host))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("listening on {} (not a loopback address) needs a bearer token: give "
                                  "--token-file FILE or set M2MLAT_TOKEN",
                                  o.host));
  return o;
}

}  // namespace

struct AgentServer::Impl {
  ServerOptions options;
  AgentBackend& backend;
  HttpServer http;
  // Stores kept open between requests: about one per request served at once.
  ReaderPool readers{options.store_path, 8};

  // notify_commit() wakes the event streams.
  StreamSignal commits;
  std::map<std::string, httplib::Server::Handler> post_handlers;  // by path

  Impl(ServerOptions o, AgentBackend& b) : options(checked(std::move(o))), backend(b), http(options) {
    configure();
  }

  // A read-only store for as long as the lease lives.
  ReaderPool::Lease reader() { return readers.lease(); }

  // The gate every request passes before routing.
  httplib::Server::HandlerResponse gate(const httplib::Request& req, httplib::Response& res) {
    if (req.headers.size() > options.max_headers) {
      fail(res, 431, fmt::format("{} header fields; at most {}", req.headers.size(), options.max_headers));
      res.set_header("Connection", "close");
      return httplib::Server::HandlerResponse::Handled;
    }
    // Bodies: never larger than the limit, and none on GET/HEAD (httplib would not read it, and its
    // bytes would be taken for the next request on the connection). A POST body a little over the limit
    // (up to kDrainFactor times) is left to httplib, which reads and discards it before its 413: closing
    // with the body unread would make the kernel reset the connection, and the client would see that
    // instead of the answer.
    if (req.has_header("Content-Length") || req.has_header("Transfer-Encoding")) {
      const auto length = req.get_header_value("Content-Length");
      const bool get = req.method == "GET" || req.method == "HEAD";
      const std::uint64_t bytes = length.size() > 18 ? UINT64_MAX : std::stoull("0" + length);
      const bool too_large = bytes > options.max_body &&
                             (get || req.method != "POST" || bytes > kDrainFactor * options.max_body);
      if (too_large || (get && (req.has_header("Transfer-Encoding") || (!length.empty() && length != "0")))) {
        fail(res, too_large ? 413 : 400,
             too_large ? fmt::format("request body larger than {} bytes", options.max_body)
                       : "GET takes no body");
        res.set_header("Connection", "close");
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    if (options.token) {
      bool ok = false;
      if (req.get_header_value_count("Authorization") == 1) {
        const std::string header = req.get_header_value("Authorization");  // parse_bearer views into it
        if (const auto token = parse_bearer(header)) ok = tokens_equal(*token, *options.token);
      }
      if (!ok) {
        fail(res, 401, "a valid 'Authorization: Bearer <token>' header is required");
        res.set_header("WWW-Authenticate", "Bearer realm=\"m2mlat\"");
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    const Route* route = nullptr;
    for (const auto& r : kRoutes)
      if (r.path == req.path) route = &r;
    if (route == nullptr) {
      fail(res, 404, "no such path (see docs/api.md)");
      return httplib::Server::HandlerResponse::Handled;
    }
    const bool get = req.method == "GET" || req.method == "HEAD";
    if ((get && !route->get) || (req.method == "POST" && !route->post) || (!get && req.method != "POST")) {
      const std::string allow = route->get && route->post ? "GET, HEAD, POST"
                                : route->get              ? "GET, HEAD"
                                                          : "POST";
      fail(res, 405, fmt::format("{} takes {}", route->path, allow));
      res.set_header("Allow", allow);
      return httplib::Server::HandlerResponse::Handled;
    }
    // A POST without Content-Length or chunked encoding has no body: answer it here, because httplib
    // would read to the end of the connection (a keep-alive client never ends it) and time out.
    if (req.method == "POST" && !req.has_header("Content-Length") && !req.has_header("Transfer-Encoding")) {
      post_handlers.at(std::string(route->path))(req, res);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  }

  // Runs a handler, turning refusals and failures into JSON errors.
  template <typename Handler>
  static httplib::Server::Handler wrap(Handler handler) {
    return [handler](const httplib::Request& req, httplib::Response& res) {
      try {
        handler(req, res);
      } catch (const RequestError& e) {
        fail(res, e.status(), e.what());
      } catch (const std::exception& e) {
        fail(res, 500, e.what());
      }
    };
  }

  Status status() {
    auto s = backend.live_status();
    const auto store = reader();
    s.api = std::string(kApiName);
    s.software_version = core::kVersion;
    s.store_id = store->store_id();
    s.last_seq = store->last_seq();
    s.now_ns = core::now_ns(CLOCK_REALTIME);
    return s;
  }

  void events(const httplib::Request& req, httplib::Response& res) {
    const auto after = parse_after(param(req, "after"));
    const auto limit = parse_limit(param(req, "limit"));
    const auto store = reader();
    // The header first, then the page cut at it: a client never sees an event beyond the seq it is told.
    const auto last = store->last_seq();
    auto page = store->events_after(after, limit);
    while (!page.empty() && page.back().seq > last) page.pop_back();
    res.set_header(std::string(kLastSeqHeader), std::to_string(last));
    res.set_content(ndjson(page), kNdjson);
  }

  void stream(const httplib::Request& req, httplib::Response& res) {
    auto cursor = parse_after(param(req, "after"));
    if (req.has_header("Last-Event-ID")) {
      if (req.get_header_value_count("Last-Event-ID") > 1)
        throw RequestError(400, "Last-Event-ID given twice");
      cursor = parse_after(req.get_header_value("Last-Event-ID"), "Last-Event-ID");
    }
    auto slot = take_stream_slot(http);  // before any header: a refusal carries none
    res.set_header("Cache-Control", "no-cache");
    res.set_header(std::string(kLastSeqHeader), std::to_string(reader()->last_seq()));
    // The committed events after the cursor, a page at a time.
    auto next = [this, cursor](std::string& out) mutable {
      const auto page = reader()->events_after(cursor, 1000);
      for (const auto& e : page) {
        fmt::format_to(std::back_inserter(out), "id: {}\nevent: event\ndata: ", e.seq);
        append_json(out, e);
        out += "\n\n";
      }
      if (!page.empty()) cursor = page.back().seq;
    };
    serve_event_stream(res, std::move(slot), commits, {options.ping_interval, options.poll_interval},
                       std::move(next));
  }

  void post_session(const httplib::Request& req, httplib::Response& res) {
    // The body is parsed as JSON whatever Content-Type says (curl -d sends a form type).
    const auto request = parse_session_request(req.body);
    const auto session = backend.begin_session(request);
    res.status = 201;
    res.set_content(nlohmann::json{{"session", to_json(session)}}.dump(
                        -1, ' ', false, nlohmann::json::error_handler_t::replace),
                    kJson);
  }

  void stop_session(httplib::Response& res) {
    const auto ended = backend.stop_session();
    if (!ended) throw RequestError(409, "no session is open");
    res.set_content(nlohmann::json{{"session", to_json(*ended)}}.dump(
                        -1, ' ', false, nlohmann::json::error_handler_t::replace),
                    kJson);
  }

  template <typename Items>
  void id_page(const httplib::Request& req, httplib::Response& res,
               Items (store::Store::*read)(std::int64_t, std::size_t) const) {
    const auto after = parse_after(param(req, "after"));
    const auto limit = parse_limit(param(req, "limit"));
    const auto store = reader();
    res.set_content(ndjson(((*store).*read)(after, limit)), kNdjson);
  }

  void routes() {
    auto& s = http.routes();
    s.Get("/v1/status", wrap([this](const httplib::Request&, httplib::Response& res) {
            res.set_content(to_json(status()).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                            kJson);
          }));
    s.Get("/v1/events",
          wrap([this](const httplib::Request& req, httplib::Response& res) { events(req, res); }));
    s.Get("/v1/events/stream",
          wrap([this](const httplib::Request& req, httplib::Response& res) { stream(req, res); }));
    s.Get("/v1/sessions", wrap([this](const httplib::Request&, httplib::Response& res) {
            nlohmann::json list = nlohmann::json::array();
            for (const auto& session : reader()->sessions()) list.push_back(to_json(session));
            res.set_content(nlohmann::json{{"sessions", list}}.dump(-1, ' ', false,
                                                                    nlohmann::json::error_handler_t::replace),
                            kJson);
          }));
    post_handlers["/v1/sessions"] =
        wrap([this](const httplib::Request& req, httplib::Response& res) { post_session(req, res); });
    post_handlers["/v1/sessions/current/stop"] =
        wrap([this](const httplib::Request&, httplib::Response& res) { stop_session(res); });
    for (const auto& [path, handler] : post_handlers) s.Post(path, handler);
    s.Get("/v1/clock-samples", wrap([this](const httplib::Request& req, httplib::Response& res) {
            id_page(req, res, &store::Store::clock_samples_after);
          }));
    s.Get("/v1/losses", wrap([this](const httplib::Request& req, httplib::Response& res) {
            id_page(req, res, &store::Store::losses_after);
          }));
    s.Get("/v1/rate-blocks", wrap([this](const httplib::Request& req, httplib::Response& res) {
            const auto after = parse_after(param(req, "after"));
            const auto limit = std::min(parse_limit(param(req, "limit")), kMaxRateBlocksPerPage);
            res.set_content(ndjson(reader()->rate_blocks_after(after, limit)), kNdjson);
          }));
    s.Get("/v1/markers", wrap([this](const httplib::Request& req, httplib::Response& res) {
            id_page(req, res, &store::Store::markers_after);
          }));
    s.Get("/metrics", wrap([this](const httplib::Request&, httplib::Response& res) {
            res.set_content(render_metrics(status(), http.counts()),
                            std::string(kMetricsContentType).c_str());
          }));
  }

  void configure() {
    auto& s = http.routes();
    s.set_default_headers({{std::string(kApiHeader), "1"}});
    s.set_pre_routing_handler(
        [this](const httplib::Request& req, httplib::Response& res) { return gate(req, res); });
    routes();
  }
};

AgentServer::AgentServer(ServerOptions options, AgentBackend& backend)
    : impl_(std::make_unique<Impl>(std::move(options), backend)) {}

AgentServer::~AgentServer() { stop(); }

void AgentServer::start() { impl_->http.start(); }

void AgentServer::stop() {
  auto& i = *impl_;
  i.commits.stop();  // the streams end, so that the server's threads can be joined
  i.http.stop();
}

int AgentServer::port() const { return impl_->http.port(); }

bool AgentServer::tls() const { return impl_->http.tls(); }

std::string AgentServer::address() const { return impl_->http.address(); }

ConnectionCounts AgentServer::counts() const { return impl_->http.counts(); }

void AgentServer::notify_commit(std::int64_t /*seq: the streams read the store*/) { impl_->commits.notify(); }

}  // namespace m2mlat::net
