// signalfd for SIGINT/SIGTERM.
#include "m2mlat/capture/stop_signal.hpp"

#include <fmt/format.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

StopSignal::StopSignal() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  if (sigprocmask(SIG_BLOCK, &set, &previous_) != 0)
    throw core::Error(core::ErrorKind::io, fmt::format("sigprocmask: {}", std::strerror(errno)));
  fd_.reset(signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC));
  if (!fd_) {
    const int err = errno;
    sigprocmask(SIG_SETMASK, &previous_, nullptr);
    throw core::Error(core::ErrorKind::io, fmt::format("signalfd: {}", std::strerror(err)));
  }
}

StopSignal::~StopSignal() {
  fd_.reset();  // before the signals are unblocked
  sigprocmask(SIG_SETMASK, &previous_, nullptr);
}

std::string StopSignal::take() {
  signalfd_siginfo info{};
  if (::read(fd_.get(), &info, sizeof info) != static_cast<ssize_t>(sizeof info)) return {};
  return info.ssi_signo == SIGINT ? "SIGINT" : info.ssi_signo == SIGTERM ? "SIGTERM" : "signal";
}

}  // namespace m2mlat::capture
