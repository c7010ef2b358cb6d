// Normal, gamma and Beta variates from + - * /, sqrt and core::portable_log, and a resample's order
// statistics from them (see order_statistics.hpp for why that is the resample's distribution).
#include "m2mlat/stats/order_statistics.hpp"

#include <algorithm>
#include <cmath>  // sqrt only: correctly rounded by IEEE 754, the same everywhere

#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/core/portable_math.hpp"

namespace m2mlat::stats {

double normal_variate(Rng& rng) {
  for (;;) {
    // 2 u - 1 is exact for u a multiple of 2^-53 in [0, 1).
    const double x = 2.0 * rng.uniform01() - 1.0;
    const double y = 2.0 * rng.uniform01() - 1.0;
    const double s = x * x + y * y;
    if (s < 1.0 && s > 0.0) return x * std::sqrt(-2.0 * core::portable_log(s) / s);
  }
}

double gamma_variate(Rng& rng, double shape) {
  const double d = shape - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    double x = 0.0, v = 0.0;
    do {
      x = normal_variate(rng);
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = rng.uniform01();
    const double x2 = x * x;
    // The squeeze accepts about 98 % without a logarithm; the second test is the exact one.
    if (u < 1.0 - 0.0331 * x2 * x2) return d * v;
    if (core::portable_log(u) < 0.5 * x2 + d * (1.0 - v + core::portable_log(v))) return d * v;
  }
}

double beta_variate(Rng& rng, double a, double b) {
  const double x = gamma_variate(rng, a);
  const double y = gamma_variate(rng, b);
  return x / (x + y);
}

void resample_order_statistics(Rng& rng, std::size_t n, std::span<const std::size_t> wanted,
                               std::span<std::size_t> ranks_out) {
  const double nn = static_cast<double>(n);
  double below = 0.0;      // U of the previous wanted order statistic (0 before the first)
  std::size_t placed = 0;  // how many uniforms lie at or below it (its k)
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    const std::size_t k = wanted[i] + 1;  // the k-th smallest, 1-based
    const double a = static_cast<double>(k - placed), b = static_cast<double>(n - k + 1);
    below = below + (1.0 - below) * beta_variate(rng, a, b);
    placed = k;
    // U < 1 gives a rank below n; a rounding to 1 (far beyond any sample's size) is clamped.
    ranks_out[i] = std::min(n - 1, static_cast<std::size_t>(below * nn));
  }
}

}  // namespace m2mlat::stats
