// Reads and writes with poll() and deadlines, plain or through OpenSSL, and the TLS handshake.
#include "m2mlat/net/connection_stream.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>

namespace m2mlat::net {

namespace {

// Milliseconds from now until `until`, rounded up (0 if passed; -1 for no end).
int poll_ms(SteadyTime until) {
  if (until == SteadyTime::max()) return -1;
  const auto left = until - std::chrono::steady_clock::now();
  if (left <= std::chrono::steady_clock::duration::zero()) return 0;
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(left).count();
  return static_cast<int>(std::min<std::int64_t>(ms, INT_MAX));
}

// Polls one socket; true when it is ready for `events` (or has an error or hang-up to report).
bool poll_socket(int socket, short events, SteadyTime until) {
  for (;;) {
    const int ms = poll_ms(until);
    if (ms == 0) return false;
    pollfd fd{socket, events, 0};
    const int n = ::poll(&fd, 1, ms);
    if (n > 0) return true;
    if (n < 0 && errno != EINTR) return false;
  }
}

void address_of(int socket, bool remote, std::string& ip, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  const int rc = remote ? ::getpeername(socket, reinterpret_cast<sockaddr*>(&addr), &len)
                        : ::getsockname(socket, reinterpret_cast<sockaddr*>(&addr), &len);
  char host[NI_MAXHOST] = "", serv[NI_MAXSERV] = "0";
  if (rc == 0)
    ::getnameinfo(reinterpret_cast<sockaddr*>(&addr), len, host, sizeof host, serv, sizeof serv,
                  NI_NUMERICHOST | NI_NUMERICSERV);
  ip = host;
  port = std::atoi(serv);
}

}  // namespace

bool set_non_blocking(int socket) {
  const int flags = ::fcntl(socket, F_GETFL);
  return flags >= 0 && ::fcntl(socket, F_SETFL, flags | O_NONBLOCK) == 0;
}

bool tls_accept(SSL* ssl, int socket, SteadyTime deadline) {
  for (;;) {
    const int rc = SSL_accept(ssl);
    if (rc == 1) return true;
    const int error = SSL_get_error(ssl, rc);
    if (error == SSL_ERROR_WANT_READ) {
      if (!poll_socket(socket, POLLIN, deadline)) return false;
    } else if (error == SSL_ERROR_WANT_WRITE) {
      if (!poll_socket(socket, POLLOUT, deadline)) return false;
    } else {
      return false;
    }
  }
}

ConnectionStream::ConnectionStream(int socket, SSL* ssl, core::Duration write_timeout)
    : socket_(socket), ssl_(ssl), write_timeout_(write_timeout) {}

void ConnectionStream::set_read_deadline(SteadyTime deadline) {
  deadline_ = deadline;
  read_ = 0;
}

bool ConnectionStream::buffered() const { return begin_ < end_ || (ssl_ && SSL_pending(ssl_) > 0); }

bool ConnectionStream::wait(short events, SteadyTime until, bool deadline_hit) const {
  if (poll_socket(socket_, events, until)) return true;
  if (deadline_hit && std::chrono::steady_clock::now() >= until) timed_out_ = true;
  return false;
}

bool ConnectionStream::wait_for_request(SteadyTime until) {
  if (buffered()) return true;  // a pipelined request
  if (!wait(POLLIN, until, false)) return false;
  // Readable may mean the peer closed: look without consuming (TLS: let fill() find out).
  if (ssl_) return true;
  char byte = 0;
  return ::recv(socket_, &byte, 1, MSG_PEEK) > 0;
}

bool ConnectionStream::fill() {
  for (;;) {
    if (ssl_) {
      const int n = SSL_read(ssl_, buffer_.data(), static_cast<int>(buffer_.size()));
      if (n > 0) {
        begin_ = 0;
        end_ = static_cast<std::size_t>(n);
        return true;
      }
      const int error = SSL_get_error(ssl_, n);
      if (error == SSL_ERROR_WANT_READ) {
        if (!wait(POLLIN, deadline_, true)) return false;
      } else if (error == SSL_ERROR_WANT_WRITE) {
        if (!wait(POLLOUT, deadline_, true)) return false;
      } else {
        return false;  // closed, or a TLS error
      }
    } else {
      const auto n = ::recv(socket_, buffer_.data(), buffer_.size(), 0);
      if (n > 0) {
        begin_ = 0;
        end_ = static_cast<std::size_t>(n);
        return true;
      }
      if (n == 0) return false;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        if (!wait(POLLIN, deadline_, true)) return false;
      } else if (errno != EINTR) {
        return false;
      }
    }
  }
}

bool ConnectionStream::is_readable() const { return buffered() || poll_socket(socket_, POLLIN, deadline_); }

bool ConnectionStream::is_writable() const {
  return poll_socket(socket_, POLLOUT, std::chrono::steady_clock::now() + write_timeout_);
}

ssize_t ConnectionStream::read(char* ptr, size_t size) {
  if (read_limit_ > 0 && read_ >= read_limit_) return -1;
  if (begin_ == end_ && !fill()) return -1;
  auto n = std::min(size, end_ - begin_);
  if (read_limit_ > 0) n = std::min(n, read_limit_ - read_);
  read_ += n;
  std::memcpy(ptr, buffer_.data() + begin_, n);
  begin_ += n;
  return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, size_t size) {
  const auto until = std::chrono::steady_clock::now() + write_timeout_;
  for (;;) {
    if (ssl_) {
      // SSL_write is retried with the same arguments after a wait, as OpenSSL requires.
      const int n = SSL_write(ssl_, ptr, static_cast<int>(std::min<size_t>(size, INT_MAX)));
      if (n > 0) return n;
      const int error = SSL_get_error(ssl_, n);
      if (error == SSL_ERROR_WANT_WRITE) {
        if (!wait(POLLOUT, until, false)) return -1;
      } else if (error == SSL_ERROR_WANT_READ) {
        if (!wait(POLLIN, until, false)) return -1;
      } else {
        return -1;
      }
    } else {
      const auto n = ::send(socket_, ptr, size, MSG_NOSIGNAL);
      if (n >= 0) return n;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        if (!wait(POLLOUT, until, false)) return -1;
      } else if (errno != EINTR) {
        return -1;
      }
    }
  }
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  address_of(socket_, true, ip, port);
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  address_of(socket_, false, ip, port);
}

}  // namespace m2mlat::net
