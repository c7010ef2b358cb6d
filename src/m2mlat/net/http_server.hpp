// The one HTTP server under the agent's API (server.hpp) and the coordinator's dashboard
// (collect/dashboard.hpp): cpp-httplib parses and routes the requests; the connections are this
// class's, so that slow, idle or abusive clients cannot keep valid ones out:
//
//  - the listening socket has SO_REUSEADDR only (a restart binds at once); httplib's default adds
//    SO_REUSEPORT, which would let another process of the same user bind the same port and receive
//    part of the connections, bearer tokens included;
//  - every connection has a thread of its own, up to max_connections; when that many are open, the
//    one that has waited longest without delivering a request head (idle between requests, or
//    still sending one) is closed to make room; only when every connection is serving a request is
//    a new one answered 503 at once (connection_budget.hpp);
//  - a request's head and body must have arrived request_timeout after its first byte, however
//    slowly the bytes come; a connection waits at most idle_timeout for a request to begin; a write
//    that finds no room for write_timeout ends the connection (connection_stream.hpp);
//  - a request head (request line and header fields) is at most max_head bytes; a body at most
//    max_body (413);
//  - event streams take a slot of max_streams (stream_slot()), so they cannot fill the budget;
//  - TLS with a PEM certificate and key; the key file must be the owner's alone (secret_file.hpp);
//  - errors httplib makes itself (400, 413, 414 ...) and handler exceptions get the JSON error body
//    of wire.hpp.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "m2mlat/core/time.hpp"

namespace httplib {
class Server;
}

namespace m2mlat::net {

// What happened to the server's connections (since it started); for tests, logs and metrics.
struct ConnectionCounts {
  std::size_t open = 0;         // connections with a thread now
  std::uint64_t accepted = 0;   // connections given a thread
  std::uint64_t evicted = 0;    // closed to make room for a newer one
  std::uint64_t refused = 0;    // answered 503 at once: every connection was serving a request
  std::uint64_t timed_out = 0;  // closed because a request's head or body missed its deadline
  std::uint64_t idle = 0;       // closed because no request began within the idle timeout
};

struct HttpServerOptions {
  std::string host = "127.0.0.1";     // an address literal; IPv6 with or without brackets
  int port = 0;                       // 0: any free port (see port())
  std::string tls_cert, tls_key;      // PEM files; both or neither (TLS)
  std::string what = "the server";    // names the server in error messages ("the dashboard")
  std::size_t max_connections = 256;  // connections open at once (one thread each)
  std::size_t max_streams = 16;       // event streams open at once
  core::Duration request_timeout = std::chrono::seconds(5);  // a request's head and body, from its first byte
  core::Duration idle_timeout = std::chrono::seconds(5);     // wait for a request to begin
  core::Duration write_timeout = std::chrono::seconds(5);    // wait for room to write
  std::size_t max_head = 64 * 1024;                          // bytes of request line and header fields
  std::size_t max_body = 64 * 1024;                          // bytes of a request body (413 beyond)
  std::size_t keep_alive_max = 100;                          // requests on one connection
};

class HttpServer {
 public:
  // Checks the options and loads the TLS certificate and key. Throws core::Error(usage): a
  // certificate without a key (or the reverse), files that cannot be loaded, a key file accessible
  // by group or others, a port out of range.
  explicit HttpServer(HttpServerOptions options);
  ~HttpServer();  // stops
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Where routes, the pre-routing gate and default headers are set, before start().
  httplib::Server& routes();

  // Binds and starts serving on a thread of its own. Throws core::Error(io) if the address cannot
  // be bound.
  void start();
  // Stops accepting, closes the waiting connections, lets the serving ones finish and joins every
  // thread. Event streams must end by themselves (their owner wakes them before calling stop()).
  // Idempotent.
  void stop();
  int port() const;             // the bound port (after start)
  std::string address() const;  // "host:port" ("[::1]:port" for IPv6)
  bool tls() const;
  ConnectionCounts counts() const;

  // A place for one event stream, held as long as the shared pointer lives (capture it in the
  // content provider); null when max_streams are open.
  class StreamSlot;
  std::shared_ptr<StreamSlot> stream_slot();
  std::size_t max_streams() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace m2mlat::net
