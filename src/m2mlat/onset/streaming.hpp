// The streaming onset detector: causal, one sample at a time, for acting at the moment a motion
// begins (switching the glass-to-glass LED at the vehicle's motion onset, `m2mlat led --on-gyro`),
// where the offline detectors (reference.hpp, flank.hpp) look at the whole trace afterwards.
//
// - rest: per axis, the rest level (the chip's bias) is learned from the first `learn_ns` of still
//   samples (a window noisier than max_rest_sd_deg_s, or with a mean beyond max_bias_deg_s, is not
//   rest: learning starts again). The learning window is then run through the smoothing below, and
//   the root mean square of the smoothed magnitude over its second half is the noise at rest (this
//   measures the chip's coloured noise as it is, not as white noise would be);
// - detection: the rates minus the rest level, smoothed per axis (exponential moving average, weight
//   smooth_alpha per sample); the first sample whose smoothed magnitude exceeds k times the noise at
//   rest (and at least min_threshold_deg_s) is an onset: add() returns true there;
// - re-arming: once the magnitude has stayed below the threshold for quiet_ns, the detector is armed
//   again; while armed it follows the rest level slowly (weight rest_alpha per sample), so a drifting
//   bias does not trigger it. The noise is the learned one: followed while armed, it rose with a slow
//   motion's sub-threshold start and kept the threshold ahead of it (slow motions went unseen).
// The detected onset lags the true one by the time the smoothed rate takes to reach the threshold:
// a fraction of a millisecond on fast motions, a few on slow ones (docs/onset.md gives the measured
// median and p95 per speed class, from tests/unit/onset/streaming_test.cpp on the gyroscope twin).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "m2mlat/core/rate_sample.hpp"

namespace m2mlat::onset {

struct StreamingOptions {
  std::int64_t learn_ns = 100'000'000;  // still time learned before the first detection, ns
  double max_rest_sd_deg_s = 1.0;       // a learning window noisier than this (any axis) is not rest
  double max_bias_deg_s = 20.0;         // nor one whose mean is further from 0 (MPU-6050 zero-rate spec)
  double rest_alpha = 1.0 / 8192;       // weight of a still sample in the rest level (1 s at 8 kHz)
  double smooth_alpha = 1.0 / 16;       // weight of a sample in the detection average
  double k = 6;                         // threshold, in rms noise of the smoothed magnitude at rest
  double min_threshold_deg_s = 0.1;     // the threshold's floor (a chip quieter than its counts), deg/s
  std::int64_t quiet_ns = 100'000'000;  // below the threshold this long re-arms the detector, ns
};

class StreamingDetector {
 public:
  enum class State { learning, armed, moving };

  // Throws core::Error(usage) naming an option out of range, or a scale that is not positive.
  explicit StreamingDetector(double counts_per_deg_s, StreamingOptions options = {});

  // Feeds the next sample (stamps in time order). Returns true when this sample is a motion's onset.
  bool add(const core::RateSample& sample);

  State state() const { return state_; }
  double threshold_deg_s() const;  // the current threshold; 0 while learning

 private:
  using Vec3 = std::array<double, 3>;
  void learn(const core::RateSample& sample, const Vec3& x);

  StreamingOptions o_;
  double scale_;  // deg/s per count
  State state_ = State::learning;
  std::vector<Vec3> learning_;        // the learning window's rates, deg/s
  std::int64_t learn_from_ns_ = 0;    // its first stamp
  Vec3 bias_{}, smooth_{};            // deg/s
  double noise2_ = 0;                 // mean square of the smoothed magnitude at rest (learned), (deg/s)^2
  std::int64_t last_above_ns_ = 0;    // while moving: the last sample above the threshold
};

}  // namespace m2mlat::onset
