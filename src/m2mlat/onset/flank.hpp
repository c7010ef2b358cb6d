// The flank detector: finds where a motion leaves the rest level, not where it crosses a threshold,
// so its onset does not lag by a time that depends on how fast the motion starts.
//
// One pass over the trace:
// - rest: per axis, the rest level (the chip's bias) and the noise are learned from the first
//   `learn_ns` of still samples (a window noisier than max_rest_sd_deg_s, or with a mean beyond
//   max_bias_deg_s, is not rest: learning starts again), then followed slowly (weight rest_alpha per
//   sample) while no motion is under way, so a drifting bias is tracked;
// - detection: the rates minus the rest level, smoothed per axis (weight smooth_alpha per sample); a
//   motion is under way while their magnitude is above k times its noise at rest; it ends after
//   quiet_ns below; one whose peak stays under min_peak_deg_s is a bump and is dropped;
// - onset: the rate along the motion's direction (the axis of the peak) is fitted, from well before
//   the detection up to where it first reaches fit_fraction of the peak, by a hinge: a rest level before t0
//   (fitted too), then that plus either c1 tau (a torque step: an actuator) or c2 tau^2 + c3 tau^3 + c4 tau^4
//   (a smooth start: a hand, whose rate and acceleration are both 0 at t0), tau = t - t0, the better fit kept
//   (hinge_fit.hpp). t0, the least-squares best (to a fraction of a sample), is the onset; its standard
//   uncertainty is the half-width of the t0 interval whose residual sum of squares stays within one residual
//   variance of the best (the profile-likelihood rule), widened for correlated noise, combined with the
//   stamp's own term (bound_ns / sqrt(3));
// - end (GY_OFF): the same fit on the falling flank, mirrored in time.
// Work per sample is a few multiplications; the fits run once per motion over its flanks.
#pragma once

#include <cstdint>

#include "m2mlat/onset/motion.hpp"

namespace m2mlat::onset {

struct FlankOptions {
  std::int64_t learn_ns = 100'000'000;    // still time learned before the first detection, ns
  double max_rest_sd_deg_s = 1.0;         // a learning window noisier than this (any axis) is not rest
  double max_bias_deg_s = 20.0;           // nor one whose mean is further from 0 (MPU-6050 zero-rate spec)
  double rest_alpha = 1.0 / 1024;         // weight of a still sample in the rest level and noise
  double smooth_alpha = 1.0 / 16;         // weight of a sample in the detection average (2 ms at 8 kHz)
  double k = 8;                           // threshold, in noise standard deviations of the smoothed magnitude
  std::int64_t quiet_ns = 20'000'000;     // below the threshold this long ends a motion, ns
  double min_peak_deg_s = 5;              // a smaller excursion is a bump, not a motion, deg/s
  double fit_fraction = 0.5;              // the fitted flank ends at this fraction of the peak rate
  std::int64_t lookback_ns = 20'000'000;  // the fit starts at least this long before the detection, ns
};

// Checks the trace (check_trace) and the options (core::Error(usage) naming the field).
Detection detect_flank(const core::RateTrace& trace, const FlankOptions& options = {});

}  // namespace m2mlat::onset
