// A random duration as the simulator draws it: `offset + X`, X of a named shape, clamped to
// [min, max]. One type describes every delay of the rig (command processing, network jitter,
// actuator lag, interrupt latency) so that all of them are configured and overridden the same way.
#pragma once

#include <cstdint>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::sim {

class Rng;

// Names are used in overrides and in docs/simulator.md: keep them stable.
enum class Shape : std::uint8_t {
  constant = 0,     // X = 0: the duration is always `offset`
  uniform = 1,      // X uniform in [0, scale)
  normal = 2,       // X normal with mean 0 and standard deviation `scale`
  exponential = 3,  // X exponential with mean `scale`
  lognormal = 4,    // X lognormal with median `scale` and standard deviation `log_sigma` of ln X
};
std::string_view to_string(Shape shape);
Shape parse_shape(std::string_view text);  // throws core::Error(usage) naming the accepted shapes

struct DurationDist {
  Shape shape = Shape::constant;
  core::Duration offset{0};                    // added to every draw (the fixed part; the mean of a normal)
  core::Duration scale{0};                     // size of the random part, see Shape
  double log_sigma = 0;                        // lognormal only: standard deviation of ln X (dimensionless)
  core::Duration min{0};                       // draws below are raised to this (delays are never negative)
  core::Duration max = std::chrono::hours(1);  // draws above are lowered to this

  friend bool operator==(const DurationDist&, const DurationDist&) = default;
};

// Shorthands for building configurations.
DurationDist constant(core::Duration value);
DurationDist uniform(core::Duration low, core::Duration width);
DurationDist normal(core::Duration mean, core::Duration sigma, core::Duration min);
DurationDist exponential(core::Duration offset, core::Duration mean);
DurationDist lognormal(core::Duration offset, core::Duration median, double log_sigma);

// One draw, in whole nanoseconds. Consumes a fixed number of variates per shape.
core::Duration sample(const DurationDist& dist, Rng& rng);

// Throws core::Error(usage) "simulator setting '<field>.<part>': ..." if the parameters make no sense (min >
// max, negative scale, negative log_sigma).
void validate(const DurationDist& dist, std::string_view field);

}  // namespace m2mlat::sim
