// One agent's puller: on its own thread, takes everything the agent has committed into the
// campaign store, exactly once, and keeps it there as it comes.
//
// A pull: /v1/status gives the agent's store_id (the origin); the campaign store's cursor for that
// origin says where to resume; /v1/sessions gives the sessions the items name; pages of
// /v1/events (10000 at a time), /v1/clock-samples, /v1/losses and /v1/rate-blocks (a gyroscope's
// raw samples, 16 blocks a page) are ingested until caught up; then the puller follows
// /v1/events/stream, committing what each arrival brought, and every second also takes new clock
// samples, losses, rate blocks, the status (for the health view) and the sessions when the open
// one changed. An event naming an unknown session makes it re-read the sessions.
// Any error marks the node unreachable, waits (100 ms doubling to 2 s) and starts a new pull from
// the store's cursor: since the cursor advances in the same transaction as the items, nothing is
// stored twice or skipped, whether the agent, the network or the coordinator went away.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "m2mlat/collect/health.hpp"
#include "m2mlat/net/client.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::store {
class Store;
}

namespace m2mlat::collect {

struct PullerOptions {
  std::string url;            // the agent's base URL, e.g. http://10.0.0.2:8470
  net::ClientOptions client;  // token, CA file, timeouts
  std::string store_path;     // the campaign store (created beforehand by the coordinator)
  store::Durability durability = store::Durability::normal;
  std::size_t page = 10000;  // events (samples, losses) per request while catching up: 1 .. 10000
  std::chrono::milliseconds backoff_min{100};  // first wait after an error, doubled up to backoff_max
  std::chrono::milliseconds backoff_max{2000};
  std::chrono::milliseconds side_interval{1000};  // status, clock samples, losses while following
  // 0: follow the event stream (SSE); otherwise poll /v1/events at this interval instead.
  std::chrono::milliseconds poll_interval{0};
  // The run's session the coordinator began on every agent (collect --start-session): an agent that
  // restarts opens a session of its own configuration; the puller then begins the run's session on it
  // again (same label and scenario), so the run goes on in one scenario. Unset: agents keep their own.
  std::optional<std::pair<std::string, std::string>> run_session;  // label, scenario
};

// Told about every failed pull: the agent's URL and what went wrong (the message names the URL).
using ErrorSink = std::function<void(const std::string& url, const std::string& message)>;

class Puller {
 public:
  Puller(PullerOptions options, std::shared_ptr<NodeTracker> tracker, ErrorSink on_error);
  ~Puller();  // stop(false)
  Puller(const Puller&) = delete;
  Puller& operator=(const Puller&) = delete;

  // Starts the thread.
  void start();
  // Asks the thread to stop and waits for it. With drain, it first takes (once, without retrying)
  // whatever the agent holds beyond the cursor and the sessions' ends: for after stop_session.
  void stop(bool drain);
  // The run is ending: the thread rejoins it no more. Returns once a rejoin under way has been
  // answered, so that a stop_session sent after it ends the rejoined session too.
  void end_run();

  // The agent's URL as normalised (scheme://host:port).
  const std::string& url() const { return control_.url(); }

  // One catch-up in the calling thread (no thread may be running): status, sessions, then pages
  // until caught up. Throws core::Error on failure. For tests and for `collect --once`.
  void catch_up_once();

 private:
  void run();
  void pull(store::Store& store);
  void catch_up(store::Store& store);
  void side_poll(store::Store& store);
  void sync_sessions();
  const store::Session* lookup(std::int64_t session_id);
  void note_status(const net::Status& status);
  void ingest(store::Store& store, std::vector<store::StoredEvent> events,
              std::vector<store::StoredClockSample> samples, std::vector<store::StoredLoss> losses,
              std::vector<store::StoredRateBlock> blocks = {}, std::vector<store::StoredMarker> markers = {});
  void take_rate_blocks(store::Store& store);  // pages of /v1/rate-blocks until caught up
  void take_markers(store::Store& store);      // pages of /v1/markers until caught up
  bool wait(std::chrono::milliseconds d);  // false if stopping
  bool stopping() const { return stop_.load(); }

  PullerOptions options_;
  std::shared_ptr<NodeTracker> tracker_;
  ErrorSink on_error_;
  net::AgentClient control_;  // everything but the stream
  net::AgentClient stream_;   // the event stream only (cancelled to stop)

  std::string origin_;                               // the agent's store_id
  std::map<std::int64_t, store::Session> sessions_;  // the origin's sessions by origin id
  std::set<std::int64_t> unsent_;                    // sessions new or changed since the last ingest
  std::optional<std::int64_t> open_session_;         // the agent's open session at its last status
  store::IngestCursor cursor_;

  std::atomic<bool> stop_{false};
  bool drain_ = false;     // stop() asked for a final catch-up
  bool draining_ = false;  // the thread is doing it (read by the thread only)
  std::mutex rejoin_mutex_;  // held across a rejoin's check and request
  bool run_ended_ = false;   // end_run() was called (under rejoin_mutex_)
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace m2mlat::collect
