// What an onset detector finds in a gyroscope's trace: each motion's onset and end (the reference
// rig's GY_ON and GY_OFF) with their standard uncertainties, and its peak rate; and the one check
// every detector makes of its input before reading it.
#pragma once

#include <cstdint>
#include <vector>

#include "m2mlat/core/rate_sample.hpp"

namespace m2mlat::onset {

struct Motion {
  std::int64_t onset_ns = 0;     // on the trace's clock, ns
  std::int64_t onset_sd_ns = 0;  // standard uncertainty (k = 1) of onset_ns, ns
  std::int64_t end_ns = 0;       // the motion's end (GY_OFF), ns; the last sample when !ended
  std::int64_t end_sd_ns = 0;    // standard uncertainty (k = 1) of end_ns, ns; 0 when !ended
  double peak_deg_s = 0;         // largest rate magnitude the detector saw in the motion, deg/s
  bool ended = true;             // false: the trace stopped before the motion did
};

struct Detection {
  std::vector<Motion> motions;  // in time order
  // The trace began in a motion: its onset is not in the trace and no motion is reported for it.
  bool began_in_motion = false;
};

// Throws core::Error(data) naming what is wrong: a counts_per_deg_s that is not a positive finite
// number, a sample not after the one before it (naming both indices and times), a negative bound.
void check_trace(const core::RateTrace& trace);

}  // namespace m2mlat::onset
