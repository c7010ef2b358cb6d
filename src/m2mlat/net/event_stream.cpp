// The server-sent-events loop: one step per call of httplib's chunked content provider.
#include "m2mlat/net/event_stream.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <algorithm>
#include <string_view>

#include "m2mlat/net/query.hpp"

namespace m2mlat::net {

void StreamSignal::notify() {
  {
    std::lock_guard lock(mutex_);
    ++notified_;
  }
  changed_.notify_all();
}

void StreamSignal::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
}

bool StreamSignal::stopping() const {
  std::lock_guard lock(mutex_);
  return stopping_;
}

std::uint64_t StreamSignal::notified() const {
  std::lock_guard lock(mutex_);
  return notified_;
}

void StreamSignal::wait(std::uint64_t seen, core::Duration timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return notified_ != seen || stopping_; });
}

std::shared_ptr<HttpServer::StreamSlot> take_stream_slot(HttpServer& server) {
  auto slot = server.stream_slot();
  if (!slot)
    throw RequestError(503, fmt::format("too many event streams (at most {})", server.max_streams()));
  return slot;
}

namespace {

using Steady = std::chrono::steady_clock;

// One stream's state, shared by the copies httplib makes of the content provider.
struct OpenStream {
  OpenStream(std::shared_ptr<HttpServer::StreamSlot> s, const StreamSignal& g, EventStreamOptions o,
             NextEvents n)
      : slot(std::move(s)), signal(g), options(o), next(std::move(n)) {}

  std::shared_ptr<HttpServer::StreamSlot> slot;
  const StreamSignal& signal;
  EventStreamOptions options;
  NextEvents next;
  Steady::time_point last_write = Steady::now();
  std::string out;  // reused between steps

  // One step: the new events if any, else a ping once idle for ping_interval, else sleep until a
  // notify() (at most the poll interval, and no later than the ping is due). False ends the stream.
  bool step(httplib::DataSink& sink) {
    while (!signal.stopping()) {
      const auto seen = signal.notified();
      out.clear();
      next(out);
      if (!out.empty()) {
        last_write = Steady::now();
        return sink.write(out.data(), out.size());
      }
      const core::Duration idle = Steady::now() - last_write;
      if (idle >= options.ping_interval) {
        last_write = Steady::now();
        static constexpr std::string_view ping = ": ping\n\n";
        return sink.write(ping.data(), ping.size());
      }
      signal.wait(seen, std::min(options.poll_interval, options.ping_interval - idle));
    }
    return false;
  }
};

}  // namespace

void serve_event_stream(httplib::Response& res, std::shared_ptr<HttpServer::StreamSlot> slot,
                        const StreamSignal& signal, EventStreamOptions options, NextEvents next) {
  auto stream = std::make_shared<OpenStream>(std::move(slot), signal, options, std::move(next));
  res.set_chunked_content_provider(
      "text/event-stream", [stream](std::size_t, httplib::DataSink& sink) { return stream->step(sink); });
}

}  // namespace m2mlat::net
