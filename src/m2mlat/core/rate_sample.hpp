// One reading of a gyroscope (an inertial motion source): the angular rate about the chip's three axes
// in the chip's own counts, and the time it is stamped with. Traces of these are kept raw (the store's
// raw samples), so that a motion's onset can be recomputed later with another detector. Kept small
// (24 bytes): a board reading at 8 kHz makes about 29 million a drive-hour.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::core {

struct RateSample {
  std::int64_t time_ns = 0;  // the stamp on the trace's clock, ns (e.g. CLOCK_REALTIME)
  // Half-width of the interval [time_ns - bound_ns, time_ns + bound_ns] that certainly holds the
  // instant the chip took the reading (e.g. half the time an I2C read took, when the time is the
  // middle of the read), ns.
  std::int32_t bound_ns = 0;
  std::array<std::int16_t, 3> raw{};  // angular rate about x, y, z, in counts (signed, as the chip gives)
};

// A run of readings from one chip, in time order.
struct RateTrace {
  Clock clock = Clock::realtime;
  // Counts per degree per second of the chip's range (e.g. 131 for an MPU-6050 at +-250 deg/s).
  double counts_per_deg_s = 131.0;
  std::vector<RateSample> samples;
};

}  // namespace m2mlat::core
