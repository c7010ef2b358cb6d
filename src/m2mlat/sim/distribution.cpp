// Drawing random durations: see distribution.hpp.
#include "m2mlat/sim/distribution.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/core/portable_math.hpp"
#include "m2mlat/sim/random.hpp"

namespace m2mlat::sim {

namespace {
constexpr std::array<std::string_view, 5> kShapeNames{"constant", "uniform", "normal", "exponential",
                                                      "lognormal"};

// Nanoseconds from a double, saturating far outside any simulated delay (a year).
std::int64_t to_ns(double ns) {
  constexpr double kLimit = 3.2e16;
  if (!(ns > -kLimit)) return static_cast<std::int64_t>(-kLimit);
  if (!(ns < kLimit)) return static_cast<std::int64_t>(kLimit);
  return std::llround(ns);
}
}  // namespace

std::string_view to_string(Shape shape) { return kShapeNames.at(static_cast<std::size_t>(shape)); }

Shape parse_shape(std::string_view text) {
  for (std::size_t i = 0; i < kShapeNames.size(); ++i)
    if (kShapeNames[i] == text) return static_cast<Shape>(i);
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("unknown shape '{}' (expected constant, uniform, normal, exponential or "
                                "lognormal)",
                                text));
}

DurationDist constant(core::Duration value) {
  return {Shape::constant, value, {}, 0, {}, std::chrono::hours(1)};
}

DurationDist uniform(core::Duration low, core::Duration width) {
  return {Shape::uniform, low, width, 0, {}, std::chrono::hours(1)};
}

DurationDist normal(core::Duration mean, core::Duration sigma, core::Duration min) {
  return {Shape::normal, mean, sigma, 0, min, std::chrono::hours(1)};
}

DurationDist exponential(core::Duration offset, core::Duration mean) {
  return {Shape::exponential, offset, mean, 0, {}, std::chrono::hours(1)};
}

DurationDist lognormal(core::Duration offset, core::Duration median, double log_sigma) {
  return {Shape::lognormal, offset, median, log_sigma, {}, std::chrono::hours(1)};
}

core::Duration sample(const DurationDist& dist, Rng& rng) {
  const auto scale = static_cast<double>(dist.scale.count());
  double x = 0;  // the random part, ns
  switch (dist.shape) {
    case Shape::constant: break;
    case Shape::uniform: x = scale * rng.uniform(); break;
    case Shape::normal: x = scale * rng.normal(); break;
    case Shape::exponential: x = scale * rng.exponential(); break;
    case Shape::lognormal: x = scale * core::portable_exp(dist.log_sigma * rng.normal()); break;
  }
  const std::int64_t ns = dist.offset.count() + to_ns(x);
  if (ns < dist.min.count()) return dist.min;
  if (ns > dist.max.count()) return dist.max;
  return core::Duration{ns};
}

void validate(const DurationDist& dist, std::string_view field) {
  auto fail = [&](std::string_view part, std::string_view what) {
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("simulator setting '{}.{}': {}", field, part, what));
  };
  if (dist.scale.count() < 0) fail("scale", "must not be negative");
  if (!(dist.log_sigma >= 0 && dist.log_sigma <= 5)) fail("log_sigma", "must be in [0, 5]");
  if (dist.min > dist.max) fail("min", "is larger than max");
  if (dist.max > std::chrono::hours(24 * 365)) fail("max", "must be at most a year");
}

}  // namespace m2mlat::sim
