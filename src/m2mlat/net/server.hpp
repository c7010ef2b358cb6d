// The agent's HTTP API server (docs/api.md) on cpp-httplib: status, committed events (paged and as
// a Server-Sent Events stream), sessions, clock samples, losses and Prometheus metrics. Events,
// samples, losses and sessions are read from the store, so only committed data is ever served;
// handlers lease read-only store::Store connections from a pool. Live counters and session control
// come from the agent runtime through AgentBackend.
//
// Connections, deadlines, the connection budget, TLS and SO_REUSEPORT are the HttpServer's
// (http_server.hpp). Every request passes one gate before routing: header count (431), bearer token
// when one is set (401), path (404) and method (405 + Allow). Bodies are limited (413); event
// streams take one of max_streams slots (503 beyond).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "m2mlat/core/time.hpp"
#include "m2mlat/net/http_server.hpp"
#include "m2mlat/net/query.hpp"
#include "m2mlat/net/wire.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::net {

// What the server asks of the agent runtime (the agent implements it; tests use a twin).
class AgentBackend {
 public:
  virtual ~AgentBackend() = default;
  // The live part of the status: node, role, session, channels, events, lost, dropped, clock and
  // started_ns. The server fills in api, software_version, store_id, last_seq and now_ns.
  virtual Status live_status() = 0;
  // Ends the open session (if any) and begins a new one; returns it as stored. Throws RequestError
  // (503) if the recorder cannot do it now.
  virtual store::Session begin_session(const SessionRequest& request) = 0;
  // Ends the open session and returns it as stored; nothing if none was open.
  virtual std::optional<store::Session> stop_session() = 0;
};

// The listening address, TLS files and connection limits are HttpServerOptions' (port 8470 here).
struct ServerOptions : HttpServerOptions {
  ServerOptions() {
    port = 8470;
    what = "the agent";
  }
  std::string store_path;            // the node's store (must exist: the recorder creates it)
  std::optional<std::string> token;  // required unless host is a loopback address
  std::size_t max_headers = 64;      // header fields of a request (431 beyond)
  core::Duration ping_interval = std::chrono::seconds(1);        // SSE comment when idle
  core::Duration poll_interval = std::chrono::milliseconds(50);  // SSE store poll without a wake-up
  core::Duration session_timeout = std::chrono::seconds(5);      // longest a session request waits
};

class AgentServer {
 public:
  // Checks the options and loads the TLS files: throws core::Error(usage) for a non-loopback host
  // without a token, or as HttpServer does (a certificate without a key, a key file readable by
  // others ...).
  AgentServer(ServerOptions options, AgentBackend& backend);
  ~AgentServer();  // stops
  AgentServer(const AgentServer&) = delete;
  AgentServer& operator=(const AgentServer&) = delete;

  // Binds and starts serving on a thread of its own. Throws core::Error(io) if the address cannot be
  // bound.
  void start();
  // Stops accepting, ends the streams and waits for every connection's thread. Idempotent.
  void stop();
  int port() const;             // the bound port (after start)
  std::string address() const;  // "host:port" ("[::1]:port" for IPv6)
  bool tls() const;
  ConnectionCounts counts() const;
  // Wakes the SSE streams: the store has committed up to `seq` (called by the recorder's thread).
  void notify_commit(std::int64_t seq);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace m2mlat::net
