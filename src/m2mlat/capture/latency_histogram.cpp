// Bucket arithmetic: index = (exponent - 4) * 32 + the 5 bits below the leading one.
#include "m2mlat/capture/latency_histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace m2mlat::capture {

int LatencyHistogram::index(std::uint64_t ns) {
  if (ns < kSub) return static_cast<int>(ns);
  const int exponent = static_cast<int>(std::bit_width(ns)) - 1;  // >= kSubBits
  const auto sub = static_cast<int>((ns >> (exponent - kSubBits)) & (kSub - 1));
  return (exponent - kSubBits + 1) * kSub + sub;
}

std::int64_t LatencyHistogram::upper(int index) {
  if (index < kSub) return index;
  const int exponent = index / kSub + kSubBits - 1;
  const auto sub = static_cast<std::uint64_t>(index % kSub);
  const std::uint64_t top = ((kSub + sub + 1) << (exponent - kSubBits)) - 1;
  return static_cast<std::int64_t>(std::min<std::uint64_t>(top, INT64_MAX));
}

void LatencyHistogram::add(std::int64_t ns) {
  ns = std::max<std::int64_t>(ns, 0);
  ++counts_[static_cast<std::size_t>(index(static_cast<std::uint64_t>(ns)))];
  ++count_;
  max_ = std::max(max_, ns);
}

std::int64_t LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return 0;
  const auto rank = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    seen += counts_[i];
    if (seen >= rank) return std::min(upper(static_cast<int>(i)), max_);
  }
  return max_;
}

}  // namespace m2mlat::capture
