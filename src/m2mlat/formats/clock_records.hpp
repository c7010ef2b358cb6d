// The clock state carried in m2mlat's events files (m2mlat-events/1), so that an offline analysis
// of the files sees the clock samples and steps a live one saw (docs/formats.md):
//
//   events CSV:   # clock: {"node":"vehicle","clock":"realtime","time_ns":...,"source":"sim",...}
//                 comment lines before the header, one per clock sample
//   events JSONL: {"format":"m2mlat-events/1","clock_sample":{"node":"vehicle",...}}
//                 a line of its own, anywhere among the events
//
// The sample's members: node, clock, time_ns, source, offset_ns, max_error_ns, est_error_ns
// (integers, ns), synchronised (true/false) and detail (an object; a step's size and window, see
// store/clock_step.hpp). Files without them read as before; a CSV reader that skips '#' lines and a
// JSONL reader that keeps objects with a "time_ns" member pass over them.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::formats {

struct ClockRecord {
  std::string node;
  core::Clock clock = core::Clock::realtime;
  std::int64_t time_ns = 0;
  std::string source;  // "adjtimex", "chrony", "ptp", "sim", "step", ...
  std::int64_t offset_ns = 0;
  std::int64_t max_error_ns = 0;
  std::int64_t est_error_ns = 0;
  bool synchronised = false;
  std::string detail_json = "{}";  // a JSON object
  friend bool operator==(const ClockRecord&, const ClockRecord&) = default;
};

inline constexpr std::string_view kClockCommentPrefix = "clock:";  // after "# "
inline constexpr std::string_view kClockMember = "clock_sample";    // the JSONL line's member

// The record as one JSON object on one line (no newline).
std::string clock_record_json(const ClockRecord& record);
// Reads the object of clock_record_json; throws core::Error(data) naming `file`:`line` and the
// member for anything missing or malformed.
ClockRecord parse_clock_record(std::string_view json, std::string_view file, long line);

}  // namespace m2mlat::formats
