#include "m2mlat/onset/uncertainty.hpp"

#include <cmath>

namespace m2mlat::onset {

double stamp_sd_ns(const core::RateSample& sample) { return sample.bound_ns / std::sqrt(3.0); }

std::int64_t crossing_sd_ns(std::span<const core::RateSample> samples, std::size_t i) {
  const double stamp = stamp_sd_ns(samples[i]);
  const double spacing =
      i > 0 ? static_cast<double>(samples[i].time_ns - samples[i - 1].time_ns) / std::sqrt(12.0) : 0.0;
  return std::llround(std::sqrt(stamp * stamp + spacing * spacing));
}

}  // namespace m2mlat::onset
