// Session control of a running recorder from other threads (the agent's HTTP API): begin a new
// session (ending the open one) or end the open one, carried out by the recorder at its next loop
// turn, i.e. at a batch boundary: the open session's buffered events are committed to it first.
// The requester waits for the outcome: the session begun, or the session ended.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>

#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::capture {

class SessionControl {
 public:
  SessionControl();
  ~SessionControl();
  SessionControl(const SessionControl&) = delete;
  SessionControl& operator=(const SessionControl&) = delete;

  // What a finished request did.
  struct Outcome {
    std::optional<store::Session> ended;  // the session it ended (as stored), if one was open
    std::optional<store::Session> begun;  // the session it began (begin requests)
  };

  // Requester side. `next` gives label, scenario, node, role and config of the new session (start
  // and id are the recorder's). Returns a ticket for wait().
  std::uint64_t request_begin(store::Session next);
  std::uint64_t request_stop();
  // The outcome of `ticket`, waiting up to `timeout`; nothing if the recorder has not carried it out
  // by then (or has stopped: see close()).
  std::optional<Outcome> wait(std::uint64_t ticket, core::Duration timeout);

  // Recorder side: a descriptor that polls readable while requests are pending.
  int fd() const { return fd_.get(); }
  struct Request {
    std::uint64_t ticket = 0;
    std::optional<store::Session> begin;  // empty: stop
  };
  // The oldest pending request, removed from the queue.
  std::optional<Request> next();
  void complete(std::uint64_t ticket, Outcome outcome);
  // The recorder has stopped: pending and later requests are never carried out.
  void close();

 private:
  std::uint64_t enqueue(std::optional<store::Session> begin);
  core::Fd fd_;  // eventfd
  std::mutex mutex_;
  std::condition_variable done_;
  std::deque<Request> pending_;
  std::map<std::uint64_t, Outcome> outcomes_;
  std::uint64_t next_ticket_ = 1;
  bool closed_ = false;
};

}  // namespace m2mlat::capture
