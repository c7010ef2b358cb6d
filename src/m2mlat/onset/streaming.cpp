// The streaming onset detector (streaming.hpp).
#include "m2mlat/onset/streaming.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/option_check.hpp"

namespace m2mlat::onset {

StreamingDetector::StreamingDetector(double counts_per_deg_s, StreamingOptions options)
    : o_(options), scale_(1.0 / counts_per_deg_s) {
  constexpr std::string_view kWho = "streaming detector";
  if (!(counts_per_deg_s > 0) || !std::isfinite(counts_per_deg_s))
    option_out_of_range(kWho, "counts_per_deg_s", counts_per_deg_s);
  check_rest_options(kWho, o_);
  if (!(o_.min_threshold_deg_s >= 0)) option_out_of_range(kWho, "min_threshold_deg_s", o_.min_threshold_deg_s);
}

double StreamingDetector::threshold_deg_s() const {
  if (state_ == State::learning) return 0;
  return std::max(o_.k * std::sqrt(noise2_), o_.min_threshold_deg_s);
}

void StreamingDetector::learn(const core::RateSample& sample, const Vec3& x) {
  if (learning_.empty()) learn_from_ns_ = sample.time_ns;
  learning_.push_back(x);
  if (sample.time_ns - learn_from_ns_ < o_.learn_ns || learning_.size() < 16) return;
  const double n = static_cast<double>(learning_.size());
  Vec3 mean{}, var{};
  for (const auto& v : learning_)
    for (std::size_t a = 0; a < 3; ++a) mean[a] += v[a] / n;
  for (const auto& v : learning_)
    for (std::size_t a = 0; a < 3; ++a) var[a] += (v[a] - mean[a]) * (v[a] - mean[a]) / (n - 1);
  for (std::size_t a = 0; a < 3; ++a)
    if (std::sqrt(var[a]) > o_.max_rest_sd_deg_s || std::abs(mean[a]) > o_.max_bias_deg_s) {
      learning_.clear();  // not rest: a motion under way; learn again from the next sample
      return;
    }
  // The noise at rest: the learning window through the detection's smoothing, its second half (the
  // average has settled by then: 1/alpha samples is 2 ms at 8 kHz).
  Vec3 smooth{};
  double sum2 = 0;
  std::size_t counted = 0;
  for (std::size_t i = 0; i < learning_.size(); ++i) {
    double mag2 = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      smooth[a] += o_.smooth_alpha * (learning_[i][a] - mean[a] - smooth[a]);
      mag2 += smooth[a] * smooth[a];
    }
    if (2 * i >= learning_.size()) sum2 += mag2, ++counted;
  }
  bias_ = mean;
  smooth_ = smooth;
  noise2_ = std::max(sum2 / static_cast<double>(std::max<std::size_t>(counted, 1)), scale_ * scale_);
  learning_.clear();
  learning_.shrink_to_fit();
  state_ = State::armed;
}

bool StreamingDetector::add(const core::RateSample& sample) {
  const Vec3 x{sample.raw[0] * scale_, sample.raw[1] * scale_, sample.raw[2] * scale_};
  if (state_ == State::learning) {
    learn(sample, x);
    return false;
  }
  double mag2 = 0;
  Vec3 d;
  for (std::size_t a = 0; a < 3; ++a) {
    d[a] = x[a] - bias_[a];
    smooth_[a] += o_.smooth_alpha * (d[a] - smooth_[a]);
    mag2 += smooth_[a] * smooth_[a];
  }
  const double threshold = threshold_deg_s();
  const bool above = mag2 > threshold * threshold;
  if (state_ == State::armed) {
    if (above) {
      state_ = State::moving;
      last_above_ns_ = sample.time_ns;
      return true;
    }
    // Still: follow the rest level slowly (a drifting bias). The noise is not followed: a slow
    // motion's start, still under the threshold, would raise it as fast as the rate rises, and the
    // threshold would run ahead of the motion.
    for (std::size_t a = 0; a < 3; ++a) bias_[a] += o_.rest_alpha * d[a];
    return false;
  }
  if (above)
    last_above_ns_ = sample.time_ns;
  else if (sample.time_ns - last_above_ns_ >= o_.quiet_ns)
    state_ = State::armed;
  return false;
}

}  // namespace m2mlat::onset
