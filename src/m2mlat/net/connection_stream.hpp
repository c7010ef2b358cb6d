// One server connection as cpp-httplib's Stream, plain or TLS, over a non-blocking socket: every
// read waits with poll() for at most the time left until the request's deadline, so however slowly
// a client trickles its bytes, reading its request ends at that deadline; every write waits at most
// the write timeout for room. Nothing here ever blocks without a bound (with TLS neither: a partial
// TLS record makes SSL_read ask to wait, and the wait has the same deadline).
#pragma once

#include <httplib.h>

#include <array>
#include <chrono>
#include <cstddef>

#include "m2mlat/core/time.hpp"

namespace m2mlat::net {

using SteadyTime = std::chrono::steady_clock::time_point;

// Makes `socket` non-blocking (the stream and the TLS handshake wait with poll instead).
bool set_non_blocking(int socket);
// The server side of a TLS handshake on a non-blocking socket, finished by `deadline` or failed.
bool tls_accept(SSL* ssl, int socket, SteadyTime deadline);

class ConnectionStream final : public httplib::Stream {
 public:
  // `ssl` null: plain TCP. Reads have no deadline until set_read_deadline().
  ConnectionStream(int socket, SSL* ssl, core::Duration write_timeout);

  // Reads fail (and timed_out() becomes true) once `deadline` has passed. Also restarts the count of
  // bytes read, which set_read_limit() bounds.
  void set_read_deadline(SteadyTime deadline);
  // Reads fail once this many bytes have been read since set_read_deadline() (0: no limit).
  void set_read_limit(std::size_t bytes) { read_limit_ = bytes; }
  // Waits until a request's first byte is there (true) or `until` passes or the peer closes (false).
  bool wait_for_request(SteadyTime until);
  bool timed_out() const { return timed_out_; }

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return socket_; }

 private:
  bool buffered() const;
  bool fill();  // reads what has arrived into buffer_; false at EOF, error, limit or deadline
  // Polls for `events` until `until`; false on timeout (setting timed_out_ if `deadline_hit`).
  bool wait(short events, SteadyTime until, bool deadline_hit) const;

  int socket_;
  SSL* ssl_;
  core::Duration write_timeout_;
  SteadyTime deadline_ = SteadyTime::max();
  std::size_t read_limit_ = 0;
  std::size_t read_ = 0;  // bytes handed out by read() since set_read_deadline()
  mutable bool timed_out_ = false;
  std::array<char, 4096> buffer_{};
  std::size_t begin_ = 0, end_ = 0;  // unread bytes of buffer_
};

}  // namespace m2mlat::net
