// The standard uncertainty a sample's stamp adds to a time found from it: the stamp lies within
// +-bound_ns of the instant the chip read the rate (uniform: bound / sqrt(3)), and a threshold
// crossing found at sample i happened somewhere after sample i - 1 (uniform over the spacing:
// spacing / sqrt(12)). Shared by the detectors so that both state their terms alike.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "m2mlat/core/rate_sample.hpp"

namespace m2mlat::onset {

// Standard uncertainty of sample i's stamp alone, ns.
double stamp_sd_ns(const core::RateSample& sample);
// Standard uncertainty of a crossing detected at sample i (stamp and spacing terms), ns, rounded.
std::int64_t crossing_sd_ns(std::span<const core::RateSample> samples, std::size_t i);

}  // namespace m2mlat::onset
