// An in-process twin of `m2mlat agent`'s HTTP API for the coordinator's tests: an httplib::Server
// on 127.0.0.1 serving a real origin store's sessions, events, clock samples, losses and rate blocks in the
// wire format of docs/api.md (encoded with net::to_json), with switchable faults: drop the
// connection in the middle of a response, answer garbage, freeze, refuse the token.
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/net/wire.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

namespace m2mlat::testing {

enum class Fault {
  none,
  drop,           // /v1/events: the connection is cut after half the lines
  garbage,        // /v1/events: 200 with a body that is not NDJSON
  freeze,         // every request waits until the fault is cleared (or the twin stops)
  no_api_header,  // answers without X-M2mlat-Api
};

class AgentTwin {
 public:
  // An origin store in `path` with one open session of `node`.
  AgentTwin(const std::string& path, std::string node, core::Role role)
      : node_(std::move(node)), role_(role) {
    store_.emplace(store::Store::open(path));
    store::Session s;
    s.node = node_;
    s.role = role_;
    s.label = "twin";
    s.start = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000);
    session_ = store_->begin_session(s);
    routes();
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~AgentTwin() {
    stopping_ = true;
    {
      std::lock_guard lock(fault_mutex_);
      fault_ = Fault::none;
    }
    fault_cv_.notify_all();
    server_.stop();
    thread_.join();
  }

  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  int port() const { return port_; }
  std::int64_t session() const { return session_; }

  // Appends `count` events (t = 1.7e18 + n ms, seqno n) in one commit; returns the last seq.
  std::int64_t append(std::size_t count) {
    std::vector<core::Event> events;
    for (std::size_t i = 0; i < count; ++i) {
      ++n_;
      core::Event e;
      e.node = node_;
      e.channel = "wheel";
      e.edge = core::Edge::falling;
      e.time = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + n_ * 1'000'000);
      e.seqno = static_cast<std::uint64_t>(n_);
      e.line_seqno = static_cast<std::uint64_t>(n_);
      events.push_back(e);
    }
    std::lock_guard lock(store_mutex_);
    store_->append_events(session_, events);
    return store_->last_seq();
  }
  void append_clock_sample(std::int64_t offset_ns) {
    store::ClockSample s;
    s.session_id = session_;
    s.time = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + n_ * 1'000'000);
    s.source = "sim";
    s.offset_ns = offset_ns;
    s.max_error_ns = 1000;
    s.est_error_ns = 100;
    s.synchronised = true;
    std::lock_guard lock(store_mutex_);
    store_->append_clock_samples(std::span<const store::ClockSample>(&s, 1));
  }
  void append_loss(std::uint64_t first, std::uint64_t count) {
    store::Loss l;
    l.session_id = session_;
    l.channel = "wheel";
    l.detected_at =
        core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + n_ * 1'000'000);
    l.first_missing = first;
    l.count = count;
    l.kind = "seqno_gap";
    std::lock_guard lock(store_mutex_);
    store_->append_losses(std::span<const store::Loss>(&l, 1));
  }
  // A block of `count` raw rate samples of the open session, numbered from `first`.
  void append_rate_block(std::uint64_t first, std::size_t count) {
    store::RateBlock b;
    b.session_id = session_;
    b.channel = "gyro";
    b.first_index = first;
    for (std::size_t i = 0; i < count; ++i)
      b.samples.push_back({1'700'000'000'000'000'000 + static_cast<std::int64_t>(first + i) * 125'000, 60'000,
                           {static_cast<std::int16_t>(i), 0, -1}});
    std::lock_guard lock(store_mutex_);
    store_->append_rate_blocks(std::span<const store::RateBlock>(&b, 1));
  }
  // A software marker in the open session (as the agent's marker port stores one).
  void append_marker(const std::string& key) {
    store::MarkerRecord m;
    m.session_id = session_;
    m.name = "planner_out";
    m.time = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + std::stoll(key));
    m.source = "kernel";
    m.key = key;
    m.origin = "udp 127.0.0.1:4000";
    std::lock_guard lock(store_mutex_);
    store_->append_markers(std::span<const store::MarkerRecord>(&m, 1));
  }
  // Ends the open session and begins another (as POST /v1/sessions does).
  std::int64_t new_session(const std::string& label, const std::string& scenario = {}) {
    std::lock_guard lock(store_mutex_);
    store_->end_session(session_, core::TimePoint::from_ns(core::Clock::realtime,
                                                           1'700'000'000'000'000'000 + n_ * 1'000'000));
    store::Session s;
    s.node = node_;
    s.role = role_;
    s.label = label;
    s.scenario = scenario;
    s.start = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + n_ * 1'000'000 + 1);
    session_ = store_->begin_session(s);
    return session_;
  }
  std::vector<store::StoredEvent> events() const {
    std::lock_guard lock(store_mutex_);
    return store_->events_after(0, 100'000'000);
  }
  std::string store_id() const {
    std::lock_guard lock(store_mutex_);
    return store_->store_id();
  }

  void set_fault(Fault fault, int times = -1) {
    {
      std::lock_guard lock(fault_mutex_);
      fault_ = fault;
      fault_times_ = times;
    }
    fault_cv_.notify_all();
  }
  void require_token(std::string token) {
    std::lock_guard lock(fault_mutex_);
    token_ = std::move(token);
  }
  int requests(const std::string& path) const {
    std::lock_guard lock(fault_mutex_);
    int n = 0;
    for (const auto& p : paths_) n += p == path;
    return n;
  }

 private:
  // The fault for this request, if it applies to its path (counting down a limited one); waits
  // while frozen (every path).
  Fault take_fault(const std::string& path) {
    std::unique_lock lock(fault_mutex_);
    paths_.push_back(path);
    const Fault f = fault_;
    if (f == Fault::freeze) {
      fault_cv_.wait(lock, [this] { return fault_ != Fault::freeze || stopping_; });
      return Fault::none;
    }
    const bool applies = (f == Fault::drop && (path == "/v1/events" || path == "/v1/events/stream")) ||
                         (f == Fault::garbage && path == "/v1/events") ||
                         (f == Fault::no_api_header && (path == "/v1/status" || path == "/v1/events"));
    if (!applies) return Fault::none;
    if (fault_times_ > 0 && --fault_times_ == 0) fault_ = Fault::none;
    return f;
  }
  bool authorised(const httplib::Request& req, httplib::Response& res) {
    std::string token;
    {
      std::lock_guard lock(fault_mutex_);
      token = token_;
    }
    if (token.empty() || req.get_header_value("Authorization") == "Bearer " + token) return true;
    res.status = 401;
    res.set_header("WWW-Authenticate", "Bearer");
    res.set_content(net::error_body(401, "missing or wrong bearer token"), "application/json");
    return false;
  }
  static std::int64_t param(const httplib::Request& req, const char* name, std::int64_t fallback) {
    return req.has_param(name) ? std::stoll(req.get_param_value(name)) : fallback;
  }

  void routes() {
    server_.set_post_routing_handler([this](const httplib::Request&, httplib::Response& res) {
      if (!no_header_) res.set_header(std::string(net::kApiHeader), "1");
      no_header_ = false;
    });
    server_.Get("/v1/status", [this](const httplib::Request& req, httplib::Response& res) {
      const auto fault = take_fault(req.path);
      if (!authorised(req, res)) return;
      if (fault == Fault::no_api_header) no_header_ = true;
      net::Status st;
      st.software_version = "0.1.0";
      st.node = node_;
      st.role = role_;
      {
        std::lock_guard lock(store_mutex_);
        st.store_id = store_->store_id();
        st.session = store_->session(session_);
        st.last_seq = store_->last_seq();
        st.events = static_cast<std::uint64_t>(store_->event_count());
        const auto samples = store_->clock_samples();
        if (!samples.empty()) st.clock = samples.back();
        for (const auto& l : store_->losses()) st.lost += l.count;
      }
      st.started_ns = 1;
      st.now_ns = 2;
      res.set_content(net::to_json(st).dump(), "application/json");
    });
    server_.Get("/v1/sessions", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      nlohmann::json j{{"sessions", nlohmann::json::array()}};
      std::lock_guard lock(store_mutex_);
      for (const auto& s : store_->sessions()) j["sessions"].push_back(net::to_json(s));
      res.set_content(j.dump(), "application/json");
    });
    server_.Post("/v1/sessions", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      const auto body = nlohmann::json::parse(req.body);
      const auto id = new_session(body.value("label", ""), body.value("scenario", ""));
      std::lock_guard lock(store_mutex_);
      res.status = 201;
      res.set_content(nlohmann::json{{"session", net::to_json(*store_->session(id))}}.dump(),
                      "application/json");
    });
    server_.Post("/v1/sessions/current/stop", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      std::lock_guard lock(store_mutex_);
      if (stopped_) {
        res.status = 409;
        res.set_content(net::error_body(409, "no session is open"), "application/json");
        return;
      }
      store_->end_session(session_, core::TimePoint::from_ns(core::Clock::realtime,
                                                             1'700'000'000'000'000'000 + n_ * 1'000'000 + 5));
      stopped_ = true;
      res.set_content(nlohmann::json{{"session", net::to_json(*store_->session(session_))}}.dump(),
                      "application/json");
    });
    server_.Get("/v1/events", [this](const httplib::Request& req, httplib::Response& res) {
      const auto fault = take_fault(req.path);
      if (!authorised(req, res)) return;
      if (fault == Fault::no_api_header) no_header_ = true;
      const auto after = param(req, "after", 0);
      const auto limit = param(req, "limit", 1000);
      if (limit < 1 || limit > 10000) {
        res.status = 400;
        res.set_content(net::error_body(400, "parameter 'limit': out of range 1..10000"), "application/json");
        return;
      }
      std::string body;
      std::int64_t last = 0;
      {
        std::lock_guard lock(store_mutex_);
        for (const auto& e : store_->events_after(after, static_cast<std::size_t>(limit)))
          body += net::to_json(e).dump() + "\n";
        last = store_->last_seq();
      }
      res.set_header(std::string(net::kLastSeqHeader), std::to_string(last));
      if (fault == Fault::garbage) {
        res.set_content("<html>proxy error</html>\n", "application/x-ndjson");
        return;
      }
      if (fault == Fault::drop) {
        // Promise the whole body, send half, then cut the connection.
        auto shared = std::make_shared<std::string>(std::move(body));
        res.set_content_provider(shared->size(), "application/x-ndjson",
                                 [shared](std::size_t offset, std::size_t, httplib::DataSink& sink) {
                                   if (offset > 0 || shared->size() < 2) return false;
                                   sink.write(shared->data(), shared->size() / 2);
                                   return true;
                                 });
        return;
      }
      res.set_content(body, "application/x-ndjson");
    });
    server_.Get("/v1/clock-samples", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      std::string body;
      std::lock_guard lock(store_mutex_);
      for (const auto& s : store_->clock_samples_after(param(req, "after", 0),
                                                       static_cast<std::size_t>(param(req, "limit", 1000))))
        body += net::to_json(s).dump() + "\n";
      res.set_content(body, "application/x-ndjson");
    });
    server_.Get("/v1/losses", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      std::string body;
      std::lock_guard lock(store_mutex_);
      for (const auto& l :
           store_->losses_after(param(req, "after", 0), static_cast<std::size_t>(param(req, "limit", 1000))))
        body += net::to_json(l).dump() + "\n";
      res.set_content(body, "application/x-ndjson");
    });
    server_.Get("/v1/rate-blocks", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      std::string body;
      std::lock_guard lock(store_mutex_);
      const auto limit = std::min(static_cast<std::size_t>(param(req, "limit", 1000)), net::kMaxRateBlocksPerPage);
      for (const auto& b : store_->rate_blocks_after(param(req, "after", 0), limit))
        body += net::to_json(b).dump() + "\n";
      res.set_content(body, "application/x-ndjson");
    });
    server_.Get("/v1/markers", [this](const httplib::Request& req, httplib::Response& res) {
      take_fault(req.path);
      if (!authorised(req, res)) return;
      std::string body;
      std::lock_guard lock(store_mutex_);
      for (const auto& m :
           store_->markers_after(param(req, "after", 0), static_cast<std::size_t>(param(req, "limit", 1000))))
        body += net::to_json(m).dump() + "\n";
      res.set_content(body, "application/x-ndjson");
    });
    server_.Get("/v1/events/stream", [this](const httplib::Request& req, httplib::Response& res) {
      const auto fault = take_fault(req.path);
      if (!authorised(req, res)) return;
      auto cursor = std::make_shared<std::int64_t>(param(req, "after", 0));
      auto idle = std::make_shared<int>(0);
      const bool drop = fault == Fault::drop;
      res.set_chunked_content_provider("text/event-stream", [this, cursor, idle, drop](
                                                                std::size_t, httplib::DataSink& sink) {
        if (stopping_) return false;
        std::vector<store::StoredEvent> events;
        {
          std::lock_guard lock(store_mutex_);
          events = store_->events_after(*cursor, 1000);
        }
        std::string text;
        for (const auto& e : events) {
          text += "id: " + std::to_string(e.seq) + "\nevent: event\ndata: " + net::to_json(e).dump() + "\n\n";
          *cursor = e.seq;
        }
        if (drop && !text.empty()) {  // half a message, then the connection goes
          sink.write(text.data(), text.size() / 2);
          return false;
        }
        if (!text.empty()) {
          *idle = 0;
          return sink.write(text.data(), text.size());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (++*idle % 40 == 0) return sink.write(": ping\n\n", 8);  // every 200 ms when idle
        return true;
      });
    });
  }

  std::string node_;
  core::Role role_;
  mutable std::mutex store_mutex_;
  std::optional<store::Store> store_;
  std::int64_t session_ = 0;
  std::int64_t n_ = 0;
  bool stopped_ = false;

  mutable std::mutex fault_mutex_;
  std::condition_variable fault_cv_;
  Fault fault_ = Fault::none;
  int fault_times_ = -1;
  std::string token_;
  std::vector<std::string> paths_;
  std::atomic<bool> no_header_{false};

  std::atomic<bool> stopping_{false};
  httplib::Server server_;
  int port_ = 0;
  std::thread thread_;
};

}  // namespace m2mlat::testing
