// Counting samples strictly above each threshold in a sorted sample.
#include "m2mlat/stats/threshold.hpp"

#include <algorithm>
#include <limits>

namespace m2mlat::stats {

std::vector<core::Duration> default_thresholds() {
  using namespace std::chrono_literals;
  return {170ms, 300ms, 400ms, 1s};
}

std::vector<ThresholdShare> threshold_shares(std::span<const std::int64_t> sorted_ns,
                                             std::span<const core::Duration> thresholds) {
  std::vector<ThresholdShare> shares;
  shares.reserve(thresholds.size());
  const std::size_t n = sorted_ns.size();
  for (const core::Duration t : thresholds) {
    const auto first_above = std::upper_bound(sorted_ns.begin(), sorted_ns.end(), t.count());
    const auto count = static_cast<std::size_t>(sorted_ns.end() - first_above);
    const double fraction = n == 0 ? std::numeric_limits<double>::quiet_NaN()
                                   : static_cast<double>(count) / static_cast<double>(n);
    shares.push_back({t, count, fraction});
  }
  return shares;
}

}  // namespace m2mlat::stats
