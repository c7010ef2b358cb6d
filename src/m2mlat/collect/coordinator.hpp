// The coordinator: one campaign store, one puller per agent, and the health of every agent.
//
// Start-up order: the campaign store is created (or opened and checked), then optionally a new
// session is begun on every agent at once (so that both boards' sessions start together), then the
// pullers start. Shutdown in reverse: optionally the agents' sessions are stopped, the pullers take
// what is left (the sessions' ends included) and stop, and the store is closed.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/collect/health.hpp"
#include "m2mlat/collect/puller.hpp"
#include "m2mlat/net/client.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::collect {

struct NewSession {
  std::string label;     // e.g. "run-3"
  std::string scenario;  // e.g. "urban"
};

struct CoordinatorOptions {
  std::vector<std::string> agents;  // base URLs, one per agent (cause, effect, more)
  std::string store_path;           // the campaign store; created if missing
  store::Durability durability = store::Durability::normal;
  net::ClientOptions client;                                       // shared by every agent's client
  std::chrono::nanoseconds stale_after = std::chrono::seconds(3);  // no contact for longer: stale
  std::optional<NewSession> start_session;                         // begin a session on every agent at start
  bool stop_session = false;                                       // stop the agents' sessions at the end
  std::chrono::milliseconds poll_interval{0};  // 0: follow the stream; otherwise poll (see Puller)
  std::size_t page = 10000;
};

class Coordinator {
 public:
  // Checks the options and the URLs; nothing is contacted yet.
  Coordinator(CoordinatorOptions options, ErrorSink on_error);
  ~Coordinator();  // stop()
  Coordinator(const Coordinator&) = delete;
  Coordinator& operator=(const Coordinator&) = delete;

  // Creates/opens the store, begins the sessions if asked, starts the pullers. Returns the
  // sessions begun (one per agent, in order). If an agent refuses the new session, throws the
  // first refusal without starting any puller (the other agents' new sessions stay open).
  std::vector<store::Session> start();
  // Stops the sessions if asked, lets each puller take what is left, stops them. Idempotent.
  void stop();

  // Without threads running: creates/opens the store and takes, from every agent in parallel,
  // what it holds beyond the cursor, once; throws the first failure (after all have finished).
  void collect_once();

  // The health of every agent, in --agent order; thread-safe, cheap (for a view refreshed often).
  std::vector<NodeHealth> health() const;
  const std::string& store_path() const { return options_.store_path; }

 private:
  CoordinatorOptions options_;
  ErrorSink on_error_;
  std::vector<std::shared_ptr<NodeTracker>> trackers_;
  std::vector<std::unique_ptr<Puller>> pullers_;
  bool running_ = false;
};

}  // namespace m2mlat::collect
