// Raw TCP clients on loopback for the servers' abuse tests (net/http_server.hpp): connections that
// send nothing, or a request head one byte at a time that never ends, and that tell whether the
// server has closed them.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "m2mlat/core/fd.hpp"

namespace m2mlat::test {

class RawClient {
 public:
  explicit RawClient(int port) : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = fd_ && ::connect(fd_.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  RawClient(RawClient&&) noexcept = default;
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;
  RawClient& operator=(RawClient&&) = delete;

  bool connected() const { return connected_; }
  bool send(std::string_view bytes) {
    return ::send(fd_.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT) ==
           static_cast<ssize_t>(bytes.size());
  }
  // Whether the server closes the connection (end of file or reset) within `timeout`; whatever it
  // sends first (an error response) is read and dropped.
  bool closed_within(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      pollfd p{fd_.get(), POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(std::max<long>(left.count(), 0))) <= 0) return false;
      char buffer[4096];
      const auto n = ::recv(fd_.get(), buffer, sizeof buffer, MSG_DONTWAIT);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) return true;
    }
  }

  // Everything the server sends until it closes the connection (or `timeout` passes).
  std::string read_until_closed(std::chrono::milliseconds timeout) {
    std::string got;
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      pollfd p{fd_.get(), POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(std::max<long>(left.count(), 0))) <= 0) return got;
      char buffer[4096];
      const auto n = ::recv(fd_.get(), buffer, sizeof buffer, MSG_DONTWAIT);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) return got;
      if (n > 0) got.append(buffer, static_cast<std::size_t>(n));
    }
  }

 private:
  core::Fd fd_;
  bool connected_ = false;
};

// `n` connections that each send a request head one byte every `interval`, never finishing it
// (after the request line, one header value grows without end), until destroyed.
class SlowLoris {
 public:
  SlowLoris(int port, std::size_t n, std::chrono::milliseconds interval) {
    for (std::size_t i = 0; i < n; ++i) clients_.emplace_back(port);
    thread_ = std::thread([this, interval] {
      static constexpr std::string_view head = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
      for (std::size_t at = 0; !stop_; ++at) {
        const char byte = at < head.size() ? head[at] : 'a';
        for (auto& c : clients_) c.send(std::string_view(&byte, 1));
        sent_ = at + 1;
        std::this_thread::sleep_for(interval);
      }
    });
  }
  ~SlowLoris() {
    stop_ = true;
    thread_.join();
  }
  SlowLoris(const SlowLoris&) = delete;
  SlowLoris& operator=(const SlowLoris&) = delete;

  std::size_t connected() const {
    std::size_t n = 0;
    for (const auto& c : clients_) n += c.connected() ? 1 : 0;
    return n;
  }
  std::size_t bytes_sent() const { return sent_; }  // by each connection
  // How many the server has closed within `timeout` (checked one after the other).
  std::size_t closed_within(std::chrono::milliseconds timeout) {
    std::size_t n = 0;
    for (auto& c : clients_) n += c.closed_within(timeout) ? 1 : 0;
    return n;
  }

 private:
  std::vector<RawClient> clients_;
  std::atomic<bool> stop_{false};
  std::atomic<std::size_t> sent_{0};
  std::thread thread_;
};

}  // namespace m2mlat::test
