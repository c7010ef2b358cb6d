// The reference rig's onset detector, kept for comparability with its published figures: each axis'
// rate smoothed by an exponential moving average (alpha = 0.05 per sample), the magnitude of the three
// smoothed rates compared with a fixed threshold (25 deg/s).
//
// Rules (as m2mlat applies them; the rig's text leaves the end and the re-arming open):
// - armed, the first sample whose smoothed magnitude is above the threshold is the onset (GY_ON);
// - the first later sample whose smoothed magnitude is below the threshold again is the end (GY_OFF);
// - after the end the detector is re-armed once `rearm_samples` consecutive samples are below the
//   threshold (a sample above restarts the count and starts no motion);
// - the averages start at the first sample's rates; a trace whose first sample is already above the
//   threshold began in a motion: that motion is not reported, and arming needs the still samples.
// The onset lags the true start by the time the smoothed rate takes to reach 25 deg/s: milliseconds
// on slow motions (docs/onset.md measures it). Uncertainty: the crossing lies between two samples
// (uniform: spacing / sqrt(12)) and each stamp within +-bound_ns (uniform: bound / sqrt(3)).
#pragma once

#include <cstdint>

#include "m2mlat/onset/motion.hpp"

namespace m2mlat::onset {

struct ReferenceOptions {
  double alpha = 0.05;                  // weight of the new sample in each axis' average (0 < alpha <= 1)
  double threshold_deg_s = 25;          // on the magnitude of the smoothed rates, deg/s
  std::int64_t rearm_samples = 10'000;  // consecutive still samples after an end, before a new onset
};

// Checks the trace (check_trace) and the options (core::Error(usage) naming the field).
Detection detect_reference(const core::RateTrace& trace, const ReferenceOptions& options = {});

}  // namespace m2mlat::onset
