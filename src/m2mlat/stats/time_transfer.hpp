// Time-transfer metrics of a phase record: how two clocks (or a clock and its reference) wander
// apart as a function of the averaging time. Used by the synchronisation test on the offsets of a
// shared pulse seen by both boards.
//
// Input: phase (time error) x_i in ns, one sample every tau0 (ns), i = 0 .. N-1; averaging time
// tau = n * tau0 for an integer factor n >= 1. All estimators are the overlapping ones (every start
// index is used), as in ITU-T G.810 / IEEE 1139 and Riley, "Handbook of Frequency Stability
// Analysis" (NIST SP 1065):
//
//   second difference   d_i(n) = x_{i+2n} - 2 x_{i+n} + x_i                     (ns)
//   ADEV^2(tau) = 1 / (2 tau^2 (N - 2n)) * sum_{i=0}^{N-2n-1} d_i(n)^2          (dimensionless)
//   MDEV^2(tau) = 1 / (2 tau^2 n^2 (N - 3n + 1)) * sum_{j=0}^{N-3n} (sum_{i=j}^{j+n-1} d_i(n))^2
//   TDEV(tau)   = tau / sqrt(3) * MDEV(tau)                                     (ns)
//   MTIE(tau)   = max over k of (max - min of x_k .. x_{k+n})                   (ns)
//
// ADEV needs N >= 2n + 1, MDEV and TDEV N >= 3n, MTIE N >= n + 1; otherwise the value is NaN.
// Slopes of log(deviation) against log(tau), for the noises a sync test meets: white phase noise
// (independent offsets) ADEV -1, MDEV -3/2, TDEV -1/2 (TDEV(tau0) = the offsets' sd); flicker phase
// noise TDEV 0; random-walk phase (white frequency noise) ADEV -1/2, TDEV +1/2.
//
// The samples must be equally spaced. Missing samples (a pulse lost on one board) are not
// interpolated: the caller counts them and says so (the estimators then treat the record as if
// the remaining samples were consecutive, which biases long taus only slightly when few are lost).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::stats {

// Each throws core::Error(usage) for n = 0 or tau0 <= 0. x_ns: phase in ns.
double adev(std::span<const double> x_ns, core::Duration tau0, std::size_t n);  // dimensionless
double mdev(std::span<const double> x_ns, core::Duration tau0, std::size_t n);  // dimensionless
double tdev(std::span<const double> x_ns, core::Duration tau0, std::size_t n);  // ns
double mtie(std::span<const double> x_ns, std::size_t n);                       // ns

// The factors 1, 2, 4, ... for which at least ADEV is defined (2n + 1 <= N), at most `limit` of them.
std::vector<std::size_t> octave_factors(std::size_t samples, std::size_t limit = 64);

struct StabilityPoint {
  std::size_t n = 0;           // tau = n * tau0
  double tau_s = 0;            // averaging time, seconds
  double adev = 0;             // fractional frequency, dimensionless (NaN if undefined)
  double mdev = 0;             // fractional frequency, dimensionless (NaN if undefined)
  double tdev_ns = 0;          // ns (NaN if undefined)
  double mtie_ns = 0;          // ns (NaN if undefined)
  std::size_t adev_terms = 0;  // second differences averaged by ADEV (N - 2n): its confidence
};

// All four at each factor, e.g. octave_factors(x.size()).
std::vector<StabilityPoint> stability(std::span<const double> x_ns, core::Duration tau0,
                                      std::span<const std::size_t> factors);

}  // namespace m2mlat::stats
