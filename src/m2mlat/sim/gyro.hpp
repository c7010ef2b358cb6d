// The simulated gyroscope: an MPU-6050-class chip on a rotating body, read by a polling reader, giving
// the core::RateTrace the real inertial source gives, from rotations whose true onsets are known.
//
// The chip: rate noise of a given density over its bandwidth (the MPU-6050 datasheet's
// 0.005 deg/s/sqrt(Hz) over the 256 Hz band of DLPF_CFG = 0: about 0.1 deg/s rms), coloured as by the
// chip's filter (first order: samples at 8 kHz are not independent, which limits any detector), a bias per
// axis drawn per chip (what is left after an offset calibration) drifting as a random walk, a sample clock
// off by a drawn fraction (the internal oscillator), the sensor mounted with a small tilt from the
// steering axis, and each reading quantised to 1/131 deg/s and clipped to int16 (+-250 deg/s range).
// Its internal low-pass filter (0.98 ms group delay at DLPF_CFG = 0) is not modelled: it delays both
// chips of a pair alike and is a constant of the configuration.
//
// The reader polls on its own schedule (one poll per nominal period) without the data-ready line: woken
// late by the scheduler (exponential, mean jitter_ns), it takes a time `before`, the bus read latches
// the rate registers after another such delay and is done read_ns later, when it takes `after`. The
// registers hold the chip's newest sample, taken at most one chip period (+2% clock tolerance) before
// the latch: the reader can only claim the sample instant lies in [before - that, after]. The stamp is
// the middle of that interval and bound_ns its half-width. As the two clocks differ, a chip sample is
// now and then read twice or never, as on a real board.
#pragma once

#include <cstdint>
#include <span>

#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/sim/gyro_motion.hpp"

namespace m2mlat::sim {

struct GyroConfig {
  double noise_density_deg_s_rthz = 0.005;  // rate noise spectral density, deg/s/sqrt(Hz)
  double noise_bandwidth_hz = 402;          // equivalent noise bandwidth (256 Hz filter x pi/2), Hz
  double bias_sd_deg_s = 1.0;               // per-axis bias drawn per chip, standard deviation, deg/s
  double bias_walk_deg_s_rts = 0.01;        // bias random walk, deg/s per sqrt(s)
  double clock_error_sd = 0.005;            // the chip's sample clock: relative error drawn per chip
  double tilt_sd = 0.05;                    // mounting tilt from the rotation axis, per component, rad
  double counts_per_deg_s = 131;            // the +-250 deg/s range
  std::int64_t period_ns = 125'000;         // nominal sample period (8 kHz), ns
  std::int64_t read_ns = 60'000;            // one I2C burst read of the rate registers, ns
  std::int64_t jitter_ns = 3'000;           // mean delay from the reader's first stamp to the read, ns

  double noise_sd_deg_s() const;  // per-sample noise, deg/s
};

// Throws core::Error(usage) naming the field out of range.
void check(const GyroConfig& config);

// One chip and its reader over [from_ns, to_ns) of true time, seeing the sum of `motions` about its
// rotation axis. `seed` and `chip` choose the random streams: two chips of one seed differ in noise,
// bias, tilt and sample phase. Deterministic: the same arguments give the same trace everywhere.
// The trace's clock is Clock::simulated (the true time: clock synchronisation is sync's concern).
core::RateTrace simulate_gyro(const GyroConfig& config, std::span<const RateMotion> motions,
                              std::int64_t from_ns, std::int64_t to_ns, std::uint64_t seed,
                              std::uint64_t chip);

}  // namespace m2mlat::sim
