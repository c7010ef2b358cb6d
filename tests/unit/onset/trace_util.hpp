// Hand-made gyroscope traces for the detector tests: a rate function of time (deg/s about z),
// sampled every `period_ns` with white noise of `noise_deg_s` on each axis and quantised as a chip
// would (131 counts per deg/s).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>

#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/sim/random.hpp"

namespace m2mlat::onset::test {

inline constexpr std::int64_t kPeriod = 125'000;  // 8 kHz, ns
inline constexpr std::int64_t kMs = 1'000'000;

inline core::RateTrace make_trace(std::int64_t duration_ns, const std::function<double(std::int64_t)>& rate_z,
                                  double noise_deg_s = 0.1, std::uint64_t seed = 1) {
  core::RateTrace trace;
  trace.counts_per_deg_s = 131;
  sim::Rng rng(seed, 0);
  for (std::int64_t t = 0; t < duration_ns; t += kPeriod) {
    core::RateSample s;
    s.time_ns = t;
    s.bound_ns = 60'000;
    const double bias[3] = {0.4, -0.7, 0.2};
    for (std::size_t a = 0; a < 3; ++a) {
      const double v = (bias[a] + (a == 2 ? rate_z(t) : 0.0) + noise_deg_s * rng.normal()) * 131;
      s.raw[a] = static_cast<std::int16_t>(std::llround(std::fmax(-32768.0, std::fmin(32767.0, v))));
    }
    trace.samples.push_back(s);
  }
  return trace;
}

// 0 before t0, then `slope` deg/s per s up to `peak`, held for `hold_ns`, then back down alike.
inline std::function<double(std::int64_t)> ramp(std::int64_t t0, double slope, double peak,
                                                std::int64_t hold_ns) {
  return [=](std::int64_t t) {
    const double rise_s = peak / slope;
    const double tau = static_cast<double>(t - t0) * 1e-9;
    const double hold_s = static_cast<double>(hold_ns) * 1e-9;
    if (tau <= 0) return 0.0;
    if (tau < rise_s) return slope * tau;
    if (tau < rise_s + hold_s) return peak;
    if (tau < 2 * rise_s + hold_s) return peak - slope * (tau - rise_s - hold_s);
    return 0.0;
  };
}

}  // namespace m2mlat::onset::test
