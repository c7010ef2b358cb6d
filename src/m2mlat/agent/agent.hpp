// The agent: one node's recorder and its HTTP API in one process. The recorder (capture::Recorder)
// runs in a thread of its own, writing to the node's store; the API server (net::AgentServer)
// serves from a thread per connection, reading through leased read-only stores. They meet in three places:
// the recorder's progress callback fills a mutex-protected snapshot of the live counters
// (/v1/status, /metrics); a commit wakes the SSE streams; session requests from the API go to the
// recorder through a capture::SessionControl and are carried out between batches.
//
// Start-up order: store (created if missing), server bound (so the port is known and a refusal
// comes before anything is recorded), the marker port bound (when asked for), recorder thread and
// marker thread, first session. Shutdown in reverse: the recorder commits what it has and ends the
// session, the marker thread stores what it read, then the server stops.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/session_control.hpp"
#include "m2mlat/capture/source.hpp"
#include "m2mlat/markers/mark_receiver.hpp"
#include "m2mlat/net/server.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::agent {

struct AgentOptions {
  std::string store_path;
  store::Options store_options;
  // The first session (node, role, label, scenario, config), batching and limits. Its control,
  // on_progress and on_commit are the agent's; before_commit is passed on (the clock monitor).
  capture::RecorderOptions recorder;
  net::ServerOptions server;  // store_path is set from store_path
  // The software markers' UDP port (`--mark-port`; docs/markers.md): datagrams stamped on arrival and
  // stored in the open session. Not opened when empty.
  struct MarkPort {
    std::string address = "127.0.0.1";  // numeric; localhost by default: marks come from this board
    int port = 0;                       // 0: any free port (tests)
  };
  std::optional<MarkPort> marks;
};

class Agent final : public net::AgentBackend {
 public:
  Agent(AgentOptions options, capture::Source& source);
  ~Agent() override;
  Agent(const Agent&) = delete;
  Agent& operator=(const Agent&) = delete;

  // Opens the store and binds the server (throws core::Error on failure; nothing is recorded yet).
  void start();
  int port() const;
  std::string address() const;
  // The marker port's "address:port" ("" without one), known after start().
  std::string mark_address() const;
  bool tls() const;

  // Records until stop_fd polls readable or the source fails; a source that finishes (a simulated
  // run's end) leaves the API serving until stop_fd. Then stops the server. Rethrows a recorder
  // failure after the server has stopped.
  capture::RecordCounters run(int stop_fd, const std::function<std::string()>& stop_name = {});

  // net::AgentBackend
  net::Status live_status() override;
  store::Session begin_session(const net::SessionRequest& request) override;
  std::optional<store::Session> stop_session() override;

 private:
  void on_progress(const capture::RecordCounters& counters);
  void before_commit(std::int64_t session_id, std::vector<store::ClockSample>& samples);
  // The marker port's thread: reads datagrams until wake_fd polls readable, stores each accepted
  // mark in the open session (its own store connection), counts the refused ones by reason.
  void mark_loop(int wake_fd);
  void refuse_mark(std::string_view reason, const std::string& detail);
  void await_first_session();  // throws net::RequestError(503) after the session timeout
  store::Session open_session(const net::SessionRequest& request);  // begin_session without the wait

  AgentOptions options_;
  capture::Source& source_;
  capture::SessionControl control_;
  std::unique_ptr<net::AgentServer> server_;
  std::unique_ptr<markers::MarkReceiver> marks_;
  std::int64_t started_ns_ = 0;

  std::mutex request_mutex_;  // one session request at a time
  std::mutex mutex_;          // guards the snapshot below
  capture::RecordCounters counters_;
  std::optional<store::Session> open_;
  std::optional<net::SessionRequest> resumed_;  // the run a killed agent's cut session was in
  // The first session is begun (or the recorder stopped first): the API's session requests wait
  // for it, so that one sent right after start-up is never replaced by the first session.
  bool first_done_ = false;
  std::condition_variable first_cv_;
  net::MarkStatus mark_status_;  // the marker port's counters (when it has one)
};

}  // namespace m2mlat::agent
