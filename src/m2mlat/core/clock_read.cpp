// Reading and sleeping on the system's POSIX clocks (see clock_read.hpp).
#include "m2mlat/core/clock_read.hpp"

#include <cerrno>

namespace m2mlat::core {

namespace {
constexpr std::int64_t kNsPerS = 1'000'000'000;
}  // namespace

std::int64_t now_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

TimePoint realtime_now() { return TimePoint::from_ns(Clock::realtime, now_ns(CLOCK_REALTIME)); }

Duration monotonic_now() { return Duration{now_ns(CLOCK_MONOTONIC)}; }

void sleep_until_ns(clockid_t clock, std::int64_t deadline_ns) {
  timespec ts{};
  ts.tv_sec = deadline_ns / kNsPerS;
  ts.tv_nsec = deadline_ns % kNsPerS;
  while (clock_nanosleep(clock, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace m2mlat::core
