// The full-loop rig's camera-to-monitor file: glass-to-glass latencies of a camera pointed at a
// monitor on one board (no clock synchronisation in it), one a line, in decimal milliseconds.
//
//   LATENCY (ms)
//   45.123456
//   47.2
//
// Each value is parsed exactly into int64 ns (core::parse_ms): up to 6 decimals, which is a whole
// nanosecond; a 7th decimal would be below a nanosecond and is refused with its file and line rather
// than rounded ("12.3456789" is an error, "12.345679" is 12345679 ns). A BOM, CRLF line ends, spaces
// around the value and blank lines are accepted; a negative value is read (the analysis counts it
// as impossible).
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace m2mlat::formats {

inline constexpr std::string_view kCameraLatencyHeader = "LATENCY (ms)";

struct CameraLatencyImport {
  std::vector<std::int64_t> latency_ns;  // in file order
  std::vector<long> lines;               // each value's line in the file, parallel to latency_ns
};

// Throws core::Error(data) naming file, line and field for a missing header or a value that is
// not a decimal number of milliseconds with at most 6 decimals.
CameraLatencyImport import_camera_latency(std::string_view text, std::string_view name);

}  // namespace m2mlat::formats
