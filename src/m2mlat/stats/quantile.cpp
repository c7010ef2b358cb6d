// Type-7 quantiles: position, interpolation, and the int64 and double front ends.
#include "m2mlat/stats/quantile.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

void check_probability(double p) {
  if (!(p >= 0.0 && p <= 1.0)) {
    throw core::Error(core::ErrorKind::usage, fmt::format("quantile probability {} is outside [0, 1]", p));
  }
}

void check_percentile(double percent) {
  if (!(percent >= 0.0 && percent <= 100.0)) {
    throw core::Error(core::ErrorKind::usage, fmt::format("percentile {} is outside [0, 100]", percent));
  }
}

QuantilePosition quantile_position(std::size_t n, double p) {
  check_probability(p);
  if (n == 0) throw core::Error(core::ErrorKind::internal, "quantile_position: empty sample");
  const double h = static_cast<double>(n - 1) * p;  // numpy: (n - 1) * quantiles
  const double j = std::floor(h);
  if (j >= static_cast<double>(n - 1)) return {n - 1, 0.0};
  return {static_cast<std::size_t>(j), h - j};
}

// The product and the sum are separate statements so that no compiler fuses them into one
// rounding (clang contracts a * b + c within an expression by default, e.g. on arm64): the same
// inputs then give the same bits everywhere, and the same as numpy, whose steps are separate.
double interpolate(double a, double b, double t) {
  const double diff = b - a;
  if (t >= 0.5) {
    const double step = diff * (1.0 - t);
    return b - step;
  }
  const double step = diff * t;
  return a + step;
}

double interpolate(std::int64_t a, std::int64_t b, double t) {
  // b >= a, so b - a fits in uint64 even where it would overflow int64.
  const double diff = static_cast<double>(static_cast<std::uint64_t>(b) - static_cast<std::uint64_t>(a));
  if (t >= 0.5) {
    const double step = diff * (1.0 - t);
    return static_cast<double>(b) - step;
  }
  const double step = diff * t;
  return static_cast<double>(a) + step;
}

double quantile(std::span<const std::int64_t> sorted, double p) {
  check_probability(p);
  if (sorted.empty()) return std::numeric_limits<double>::quiet_NaN();
  const QuantilePosition at = quantile_position(sorted.size(), p);
  if (at.fraction == 0.0) return static_cast<double>(sorted[at.lower]);
  return interpolate(sorted[at.lower], sorted[at.lower + 1], at.fraction);
}

double quantile(std::span<const double> sorted, double p) {
  check_probability(p);
  if (sorted.empty()) return std::numeric_limits<double>::quiet_NaN();
  const QuantilePosition at = quantile_position(sorted.size(), p);
  if (at.fraction == 0.0) return sorted[at.lower];
  return interpolate(sorted[at.lower], sorted[at.lower + 1], at.fraction);
}

double median(std::vector<std::int64_t> values) {
  std::sort(values.begin(), values.end());
  return quantile(std::span<const std::int64_t>(values), 0.5);
}

}  // namespace m2mlat::stats
