// The one server-sent-events writer under every event stream the servers offer: the agent's
// /v1/events/stream (server.hpp, docs/api.md) and the dashboard's /api/live/stream
// (collect/dashboard.hpp, docs/dashboard.md). What differs between them is given to it: where the
// next events come from and how each is rendered (NextEvents), and how long an idle stream waits
// before a ping. What is the same is here: a stream writes whatever is new at once, sleeps until
// its server signals that something may be new (or the poll interval passes), sends the comment
// ": ping\n\n" after ping_interval without a write (so that proxies and clients see it alive, and
// the server sees a client that went), and ends when its server stops or the client goes.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "m2mlat/core/time.hpp"
#include "m2mlat/net/http_server.hpp"

namespace httplib {
struct Response;
}

namespace m2mlat::net {

// Wakes the event streams of one server: the producer calls notify() after something new is
// readable (a commit, a snapshot); stop() ends every stream at its next step. Thread-safe.
class StreamSignal {
 public:
  void notify();
  // Before HttpServer::stop(), which waits for the streams to end.
  void stop();
  bool stopping() const;
  // How many notify() calls so far; taken before looking for events, so that a notify() in
  // between is never missed by wait().
  std::uint64_t notified() const;
  // Returns when notify() has been called more than `seen` times in all, at stop(), or after
  // `timeout`.
  void wait(std::uint64_t seen, core::Duration timeout) const;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::uint64_t notified_ = 0;
  bool stopping_ = false;
};

struct EventStreamOptions {
  core::Duration ping_interval = std::chrono::seconds(1);  // ": ping" after this long without a write
  // The longest sleep without a notify() before the next events are asked for again (for sources
  // that can grow without one, as a store written by another process).
  core::Duration poll_interval = std::chrono::seconds(1);
};

// Appends the events after the stream's position to `out`, each a complete message
// ("id: N\nevent: TYPE\ndata: ...\n\n"), and moves the position past them; appends nothing when
// there is nothing new. Called on the stream's connection thread, never twice at once.
using NextEvents = std::function<void(std::string& out)>;

// A place for one more stream on `server`, held until the stream ends; throws RequestError(503)
// naming the limit when all max_streams are taken.
std::shared_ptr<HttpServer::StreamSlot> take_stream_slot(HttpServer& server);

// Answers `res` with a text/event-stream (chunked) that writes what `next` gives, pings when idle
// and ends when `signal` stops or the client goes. Holds `slot` and `next` until then. `signal`
// must outlive the server's connections (stop the server before destroying it).
void serve_event_stream(httplib::Response& res, std::shared_ptr<HttpServer::StreamSlot> slot,
                        const StreamSignal& signal, EventStreamOptions options, NextEvents next);

}  // namespace m2mlat::net
