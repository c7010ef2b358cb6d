// The kernel's view of its clock discipline, read with clock_adjtime(CLOCK_REALTIME) in read-only
// mode (modes = 0): whether a synchronisation daemon has told the kernel the clock is synchronised
// (STA_UNSYNC clear, state not TIME_ERROR), the daemon's error bounds, the frequency correction in
// force, the status bits and the TAI offset. One read costs about a microsecond (a system call and
// no I/O), so it can be taken with every batch of events.
//
// Also the paired reading of CLOCK_REALTIME and CLOCK_MONOTONIC_RAW that step detection needs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/store/records.hpp"

struct timex;

namespace m2mlat::sync {

struct KernelClockState {
  bool available = false;  // false: the call failed (error says why)
  std::string error;
  int state = 0;               // the call's return value: TIME_OK (0) .. TIME_ERROR (5)
  int status = 0;              // STA_* bits
  bool synchronised = false;   // STA_UNSYNC clear and state != TIME_ERROR
  std::int64_t offset_ns = 0;  // the PLL offset still being corrected, ns (kernel: us, or ns with STA_NANO)
  std::int64_t max_error_ns = 0;  // maxerror, ns (kernel: us; grows by 500 ppm while no daemon updates it)
  std::int64_t est_error_ns = 0;  // esterror, ns (kernel: us)
  std::int64_t freq_scaled = 0;   // the frequency correction as the kernel keeps it: ppm * 2^16
  std::int64_t tick_us = 0;       // length of a clock tick, us (10000 at USER_HZ 100 = no adjustment)
  int tai = 0;                    // TAI - UTC, s (0 when no daemon set it)
  // The total rate correction of CLOCK_REALTIME against the raw oscillator, ppm: freq plus the tick
  // adjustment (a tick 1 us longer than 10000 us adds 100 ppm).
  double rate_ppm() const;
};

// Interprets a struct timex filled by adjtimex/clock_adjtime, the call's return value and, when it
// failed (rc < 0), its errno.
KernelClockState kernel_clock_state(const struct timex& tx, int rc, int error_number = 0);
// Reads the kernel's state now (clock_adjtime(CLOCK_REALTIME, {modes = 0})); never changes the clock.
KernelClockState read_kernel_clock();

// The names of the set STA_* bits, e.g. {"PLL", "NANO"}.
std::vector<std::string> status_names(int status);
// "TIME_OK", "TIME_INS", ... "TIME_ERROR" (or "unknown").
std::string state_name(int state);

// The state as a clock sample (source "adjtimex") taken at `time` (CLOCK_REALTIME).
store::ClockSample adjtimex_sample(const KernelClockState& state, core::TimePoint time);

// CLOCK_REALTIME and CLOCK_MONOTONIC_RAW read together: raw is the midpoint of two raw reads around
// the realtime read, so the pair is off by at most half of window_ns.
struct ClockPair {
  std::int64_t realtime_ns = 0;
  std::int64_t monotonic_raw_ns = 0;
  std::int64_t window_ns = 0;  // time between the two raw reads, ns
};
ClockPair read_clock_pair();

}  // namespace m2mlat::sync
