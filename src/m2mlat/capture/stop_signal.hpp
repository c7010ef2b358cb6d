// SIGINT and SIGTERM as a readable descriptor (signalfd), so that the capture loop sees a stop
// request in the same poll as its events, and no work happens in a signal handler. While a
// StopSignal exists the two signals are blocked (delivered only through the descriptor); the
// previous mask is restored when it goes.
#pragma once

#include <csignal>
#include <string>

#include "m2mlat/core/fd.hpp"

namespace m2mlat::capture {

class StopSignal {
 public:
  StopSignal();
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  int fd() const { return fd_.get(); }
  // The name of the signal that arrived ("SIGINT"), consuming it; empty if none is pending.
  std::string take();

 private:
  core::Fd fd_;
  sigset_t previous_{};
};

}  // namespace m2mlat::capture
