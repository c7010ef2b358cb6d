// Helpers shared by the simulator's tests: quantiles of latencies and small run configurations.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::sim::test {

// Linear-interpolation quantile (type 7) of `values`, p in [0, 1].
inline double quantile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const double pos = p * static_cast<double>(values.size() - 1);
  const auto i = static_cast<std::size_t>(pos);
  if (i + 1 >= values.size()) return values.back();
  const double frac = pos - static_cast<double>(i);
  return values[i] * (1 - frac) + values[i + 1] * frac;
}

inline double iqr(const std::vector<double>& values) {
  return quantile(values, 0.75) - quantile(values, 0.25);
}

inline std::vector<double> true_latencies_ms(const Simulation& run) {
  std::vector<double> out;
  for (const TruePair& pair : run.pairs) out.push_back(static_cast<double>(pair.true_latency.count()) / 1e6);
  return out;
}

// The default rig with ideal sensors, for tests that count edges.
inline RigConfig ideal_config(std::int64_t manoeuvres, std::uint64_t seed = 1) {
  RigConfig config;
  config.manoeuvres = manoeuvres;
  config.seed = seed;
  clear_imperfections(config);
  return config;
}

}  // namespace m2mlat::sim::test
