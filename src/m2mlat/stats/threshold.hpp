// The share of samples above latency limits.
//
// The defaults are the human-factors limits used in teleoperation latency studies (170, 300 and
// 400 ms) and 1 s; callers may pass any list. A sample counts as above a threshold when it is strictly
// greater: a latency of exactly 300 ms is not above 300 ms. The comparison is made on the integer
// nanoseconds, so it is exact.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::stats {

// {170 ms, 300 ms, 400 ms, 1 s}.
std::vector<core::Duration> default_thresholds();

struct ThresholdShare {
  core::Duration threshold{0};
  std::size_t count_above = 0;  // samples > threshold
  double fraction_above = 0.0;  // count_above / n, in [0, 1]; NaN for an empty sample
  friend bool operator==(const ThresholdShare&, const ThresholdShare&) = default;
};

// One share per threshold, in the order given. `sorted_ns` must be ascending (binary search).
std::vector<ThresholdShare> threshold_shares(std::span<const std::int64_t> sorted_ns,
                                             std::span<const core::Duration> thresholds);

}  // namespace m2mlat::stats
