// A clock step as a stored clock sample. Every source that can reveal a step of CLOCK_REALTIME
// (the clock monitor's realtime - monotonic_raw check, the kernel log's printk stamps, the kernel's
// adjtimex status, chronyd's log, the simulator) writes it as a store::ClockSample with source
// "step", so that stores, events files and the analysis carry one kind of record:
//
//   time          = at_ns: the stepped clock's reading from which every stamp of that board is
//                   surely after the step (the new timescale)
//   offset_ns     = the step's size, ns (new reading - old reading; 0 when unknown)
//   max_error_ns  = a bound on the error of that size, ns (kUnknownSize when the size is unknown)
//   est_error_ns  = its standard uncertainty (k = 1), ns (likewise)
//   synchronised  = false (a step is never a synchronised state)
//   detail_json   = {"from_ns", "to_ns", "step_ns", "earliest_ns", "size_known", "origin", ...}
//
// earliest_ns is the earliest reading of the new timescale the step can have happened at (a
// detector that sees the step only between two readings knows it to within that window); stamps
// in [earliest_ns, at_ns) cannot be placed before or after the step by their values alone.
// Records of the clock monitor written before these members existed ({from_ns, to_ns, step_ns,
// unexplained_ns}, with max_error_ns = |step_ns|) read as a step of known size at to_ns, its size
// bounded by what the rates explained (|step_ns| - unexplained_ns).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "m2mlat/store/records.hpp"

namespace m2mlat::store {

inline constexpr std::string_view kStepSource = "step";
inline constexpr std::int64_t kUnknownSize = std::numeric_limits<std::int64_t>::max();

struct ClockStep {
  std::int64_t at_ns = 0;        // stamps at or after this are surely after the step (new timescale), ns
  std::int64_t earliest_ns = 0;  // the step happened at a reading in [earliest_ns, at_ns], ns
  std::optional<std::int64_t> size_ns;  // new - old reading, ns; unset: a step of unknown size
  std::int64_t size_max_ns = kUnknownSize;  // bound on the error of size_ns, ns
  std::int64_t size_est_ns = kUnknownSize;  // its standard uncertainty (k = 1), ns
  // "monitor", "kernel_log", "adjtimex", "chrony", "sim"; a step taken over from the other board's:
  // "followed", "follow_unchecked" (analysis/import_follow.hpp)
  std::string origin;
  friend bool operator==(const ClockStep&, const ClockStep&) = default;
};

// Lines of a log whose realtime stamps are on no clock the analysis can place (kernel_log_steps.hpp):
// one line that disagrees with the lines on both sides of it ("outlier"), or the lines a board
// stamped before its clock was first set ("before_sync"). Their events are left out before pairing,
// counted by reason; stored as a clock sample of source "unknown_clock" (time = from_ns, detail
// {"to_ns", "lines", "reason"}) so that an imported log keeps them, and merge and export carry them.
// No stamp of a kept line of the log lies in [from_ns, to_ns].
inline constexpr std::string_view kUnknownClockSource = "unknown_clock";
struct UnknownClock {
  std::int64_t from_ns = 0, to_ns = 0;  // the lines' realtime stamps, ns (inclusive)
  std::int64_t lines = 0;               // lines in the range
  std::string reason;                   // "outlier" or "before_sync"
  friend bool operator==(const UnknownClock&, const UnknownClock&) = default;
};
ClockSample unknown_clock_sample(const UnknownClock& lines, core::Clock clock = core::Clock::realtime);
std::optional<UnknownClock> unknown_clock_of(const ClockSample& sample);

// The step as a clock sample on `clock` (session_id 0: the caller sets it).
ClockSample step_clock_sample(const ClockStep& step, core::Clock clock = core::Clock::realtime);
// The step a "step" sample records; nullopt for any other sample or a detail that is not a step's.
std::optional<ClockStep> clock_step_of(const ClockSample& sample);

}  // namespace m2mlat::store
