// One owned file descriptor (a file, a socket, an eventfd, an epoll or signal descriptor, a pipe's
// end): move-only, and closed when its owner goes, so that no early return or exception leaks one
// and no class closes by hand. It lives in core, the bottom folder, because descriptors are held at
// every level: store (a new store's file), formats (input files), net (sockets, secret files), sync
// (a child's pipes), capture (GPIO line requests, kmsg, eventfds, signalfd) and core's own output
// writer.
#pragma once

#include <unistd.h>

#include <utility>

namespace m2mlat::core {

class Fd {
 public:
  Fd() = default;
  // Takes `fd` over (a negative value holds nothing, so the result of open(2) goes in directly).
  explicit Fd(int fd) noexcept : fd_(fd) {}
  Fd(Fd&& other) noexcept : fd_(other.release()) {}
  Fd& operator=(Fd&& other) noexcept {
    if (this != &other) reset(other.release());
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }

  int get() const noexcept { return fd_; }  // -1 when nothing is held
  explicit operator bool() const noexcept { return fd_ >= 0; }

  // Hands the descriptor to the caller, who closes it from now on; holds nothing afterwards.
  int release() noexcept { return std::exchange(fd_, -1); }
  // Closes the descriptor held (if any) and takes `fd` over.
  void reset(int fd = -1) noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }
  // Closes now and says how it went: close(2)'s result, 0 or -1 with errno (a written file's last
  // error may only show here); 0 when nothing was held. Holds nothing afterwards.
  int close() noexcept { return fd_ >= 0 ? ::close(release()) : 0; }

 private:
  int fd_ = -1;
};

}  // namespace m2mlat::core
