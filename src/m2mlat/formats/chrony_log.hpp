// chronyd's own messages about clock steps, read from a log: the journal (`journalctl -u chrony -o
// short-iso-precise`, -o short-iso, or -o json: MESSAGE at __REALTIME_TIMESTAMP), rsyslog's high-precision files (RFC 3339 stamps), or
// chronyd's own log (`-d`, `logfile`: "2026-06-01T09:00:00Z ..."). The messages (chrony's
// sources: reference.c, sched.c):
//   "System clock was stepped by X seconds"   chronyd stepped the clock by X (makestep, chronyc makestep)
//   "System clock wrong by X seconds (step)"  chronyd -q stepped it by X
//   "System's initial offset : X seconds fast of true (step)"
//                                             initstepslew stepped it by -X ("slow": by +X; "(slew)": no step)
//   "System clock was stepped for leap second" a leap second: a step of unknown sign (1 s)
//   "Forward time jump detected!" / "Backward time jump detected!"
//                                             something else set the clock: a step of unknown size
//   "Could not step system clock"             the step announced just before (a "(step)" line within
//                                             2 s) did not happen: it is taken back, and counted
// "System clock wrong by X seconds" without "(step)" ("adjustment started", "(ignored)", or the
// notice before a "stepped by" line) is a slew, a dry run or the same step again: not a step.
// X is exact decimal seconds (chrony prints microseconds: the size is known to +-0.5 us).
//
// Each line's timestamp (the logging host's CLOCK_REALTIME after the step, to its resolution)
// places the step: it happened at most `slack` before the stamp and before the stamp's next tick.
// Classic syslog stamps ("Mar 14 14:06:28") name no year and no zone: refused, naming the line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace m2mlat::formats {

struct ChronyStep {
  long line = 0;                        // in the file, 1-based
  std::int64_t time_ns = 0;             // the line's stamp, CLOCK_REALTIME ns since 1970 (UTC)
  std::int64_t resolution_ns = 0;       // of that stamp (1 s for "..:28Z", 1 us for ".123456")
  std::optional<std::int64_t> size_ns;  // new - old reading; unset for a time jump chronyd only saw
  friend bool operator==(const ChronyStep&, const ChronyStep&) = default;
};

struct ChronyLogImport {
  std::vector<ChronyStep> steps;   // in file order; a step reported twice is kept once
  std::size_t chrony_lines = 0;    // lines with a chronyd message about the system clock
  std::size_t ignored_lines = 0;   // every other line
  std::size_t failed_steps = 0;    // "Could not step system clock" lines
};

// Throws core::Error(data) naming file:line for a step line whose stamp cannot be read, and for a
// file without any chronyd clock message ("is it chronyd's log?").
ChronyLogImport import_chrony_log(std::string_view text, std::string_view name);

// An RFC 3339 / ISO 8601 time at the start of `text` ("2026-06-01T09:00:00.123456+02:00", "...Z",
// "+0200", a space for the T), as UTC ns; its resolution and length. nullopt if there is none.
struct LogStamp {
  std::int64_t ns = 0;
  std::int64_t resolution_ns = 0;
  std::size_t length = 0;
};
std::optional<LogStamp> parse_log_stamp(std::string_view text);

}  // namespace m2mlat::formats
