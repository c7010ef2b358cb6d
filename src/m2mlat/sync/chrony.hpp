// chrony's view of the clock, read with `chronyc -c -n -m tracking sources` (one process, CSV).
//
// Field order of chrony 4.3's CSV output (client.c, print_report in CSV mode):
//   tracking: ref id (8 hex digits), ref name or address, stratum, ref time (s.ns since the epoch),
//             system time correction (s; positive = the system clock is SLOW), last offset (s),
//             RMS offset (s), frequency (ppm; positive = the clock runs FAST without correction),
//             residual frequency (ppm), skew (ppm), root delay (s), root dispersion (s),
//             update interval (s), leap status ("Normal", "Insert second", "Delete second",
//             "Not synchronised", "Invalid")                                         -> 14 fields
//   sources:  mode (^ server, = peer, # refclock), state (* selected, + combined, - not combined,
//             x falseticker, ~ too variable, ? unusable), name/address, stratum, poll (log2 s),
//             reach (octal), seconds since the last sample (4294967295 = never), adjusted offset (s),
//             measured offset (s), error bound (s)                                   -> 10 fields
// Seconds are printed with 9 decimals and parsed exactly into int64 ns (core::parse_seconds).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/process/command_runner.hpp"

namespace m2mlat::sync {

struct ChronyTracking {
  std::uint32_t ref_id = 0;
  std::string ref_name;  // address or refclock name; empty for the local reference
  int stratum = 0;
  std::int64_t ref_time_ns = 0;         // last update from the reference, ns since the epoch (UTC)
  std::int64_t system_offset_ns = 0;    // system clock - true time, ns (positive = ahead); the
                                        // negated correction chrony prints
  std::int64_t last_offset_ns = 0;      // offset at the last update, ns (positive = ahead)
  std::int64_t rms_offset_ns = 0;       // long-term average of the offset, ns
  double freq_ppm = 0;                  // frequency error corrected, ppm (positive = runs fast)
  double residual_freq_ppm = 0;         // ppm
  double skew_ppm = 0;                  // error bound of the frequency, ppm
  std::int64_t root_delay_ns = 0;       // total round-trip delay to the stratum-1 source, ns
  std::int64_t root_dispersion_ns = 0;  // total dispersion accumulated to it, ns
  std::int64_t update_interval_ns = 0;  // between the last two updates, ns
  std::string leap_status;              // as chrony prints it
  bool synchronised() const { return leap_status != "Not synchronised" && leap_status != "Invalid"; }
};

struct ChronySource {
  char mode = ' ';   // '^' server, '=' peer, '#' reference clock
  char state = ' ';  // '*' selected, '+', '-', 'x', '~', '?'
  std::string name;
  int stratum = 0;
  int poll = 0;                           // log2 of the polling interval, s
  int reach = 0;                          // reachability register (8 bits)
  std::optional<std::int64_t> last_rx_s;  // seconds since the last sample; empty: never
  std::int64_t adjusted_offset_ns = 0;    // positive = local clock ahead of the source
  std::int64_t measured_offset_ns = 0;
  std::int64_t error_ns = 0;  // the "+/-" estimated error of the last sample
};

struct ChronyReport {
  ChronyTracking tracking;
  std::vector<ChronySource> sources;
};

// Pure parsers (no I/O), for tests and fuzzing. `where` names the input in errors; its line is set
// per line. Errors: core::Error(data) naming the line and field.
ChronyTracking parse_chrony_tracking_line(std::string_view line, const core::Location& where);
ChronySource parse_chrony_source_line(std::string_view line, const core::Location& where);
// The output of `chronyc -c -m tracking sources`: exactly one 14-field tracking line and any
// number of 10-field source lines; blank lines are ignored.
ChronyReport parse_chronyc_output(std::string_view text, const core::Location& where);

// The report as a clock sample (source "chrony") taken at `time`:
//   offset_ns    = tracking.system_offset_ns
//   max_error_ns = |system offset| + root dispersion + root delay / 2 (chrony's own bound on the
//                  distance to true time)
//   est_error_ns = max(RMS offset, |system offset|): the typical offset chrony has been seeing, but
//                  never less than the offset it is correcting right now (after a disturbance the
//                  RMS lags behind)
// detail_json holds every tracking field and the sources.
store::ClockSample chrony_sample(const ChronyReport& report, core::TimePoint time);

struct ChronycOptions {
  std::string program = "chronyc";
  std::string host;  // -h: an address or a command socket path (starting with '/'); empty: chronyc's default
  int port = 0;      // -p: the command port for an address; 0: chronyc's default
  core::Duration timeout = std::chrono::seconds(2);
};

// The chronyc command line for one report.
std::vector<std::string> chronyc_argv(const ChronycOptions& options);

// Runs chronyc and parses its output. Throws core::Error(io) when chronyc cannot be run or fails
// (the message carries its output), core::Error(data) when the output does not parse.
ChronyReport read_chrony(process::CommandRunner& runner, const ChronycOptions& options);

}  // namespace m2mlat::sync
