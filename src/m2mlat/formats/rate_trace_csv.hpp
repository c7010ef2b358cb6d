// A gyroscope's raw trace as a file (format m2mlat-gyro/1): what `m2mlat gyro` writes, and what an
// onset detector can read back later. One line per reading, the chip's own counts, nothing derived:
//
//   # format: m2mlat-gyro/1
//   # clock: realtime
//   # counts_per_deg_s: 131
//   # source: mpu6050 /dev/i2c-1 address 0x68, period 1000000 ns
//   time_ns,bound_ns,x,y,z
//   1764086400000512345,48211,12,-3,0
//
// time_ns: the stamp (ns on the named clock); bound_ns: the half-width of the interval around it
// that holds the instant of the reading (ns, >= 0); x, y, z: the angular rate in counts (signed
// 16-bit; divide by counts_per_deg_s for deg/s). Lines in time order. Other "#" lines before the
// header are comments (the writer puts the source there).
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/rate_sample.hpp"

namespace m2mlat::formats {

inline constexpr std::string_view kRateTraceFormat = "m2mlat-gyro/1";

// `comments`: lines written after the fixed header lines, each prefixed with "# " (no line breaks).
void write_rate_trace_csv(std::ostream& out, const core::RateTrace& trace,
                          const std::vector<std::string>& comments = {});

// Throws core::Error(data) naming `name`, the line and the field for anything malformed: a missing or
// other format line, a bad clock or scale, a header other than the one above, a field that is not
// an integer or out of range, a time before the previous line's, a file cut mid-line.
core::RateTrace read_rate_trace_csv(std::string_view text, std::string_view name);

}  // namespace m2mlat::formats
