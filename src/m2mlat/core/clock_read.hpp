// Reading and sleeping on the system's POSIX clocks in int64 ns: the one place a timespec becomes
// nanoseconds (every reader of "now" in the capture, sync, network and test code goes through it).
#pragma once

#include <time.h>

#include <cstdint>

#include "m2mlat/core/time.hpp"

namespace m2mlat::core {

// The clock (CLOCK_REALTIME, CLOCK_MONOTONIC, ...) now, ns since its epoch.
std::int64_t now_ns(clockid_t clock);
// CLOCK_REALTIME now, as a time point on Clock::realtime (session bounds, loss times).
TimePoint realtime_now();
// CLOCK_MONOTONIC now, ns since boot (limits and intervals).
Duration monotonic_now();
// Sleeps until the clock reads `deadline_ns` (absolute: no error accumulates from one deadline to the
// next); a signal does not cut the sleep short.
void sleep_until_ns(clockid_t clock, std::int64_t deadline_ns);

}  // namespace m2mlat::core
