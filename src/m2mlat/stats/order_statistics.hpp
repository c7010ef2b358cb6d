// A bootstrap resample's order statistics drawn directly, without drawing the resample.
//
// A resample draws n ranks uniformly with replacement from {0, ..., n-1}: rank floor(n U) for a
// uniform U in [0, 1). Ranks are monotone in U, so the resample's k-th smallest rank is
// floor(n U_(k)), U_(k) the k-th smallest of n uniforms, and U_(k) ~ Beta(k, n - k + 1). Given
// U_(k) = u, the other n - k uniforms above it are uniform on [u, 1), so a later order statistic
// U_(m), m > k, is u + (1 - u) Beta(m - k, n - m + 1). A few order statistics of a resample thus
// cost a few Beta variates instead of n draws, with the same distribution, jointly.
//
// Every variate is specified operation by operation (Marsaglia's polar method for the normal,
// Marsaglia and Tsang's method for the gamma, core/portable_math.hpp's logarithm), so the same
// stream gives the same ranks on every platform; tests/unit/stats/reference_values.py re-implements
// them in Python and the tests compare the two.
#pragma once

#include <cstddef>
#include <span>

#include "m2mlat/stats/rng.hpp"

namespace m2mlat::stats {

// Standard normal: Marsaglia's polar method (uniform points in the unit disc; the second normal of
// each accepted point is not kept, so each call starts from fresh draws).
double normal_variate(Rng& rng);

// Gamma(shape, 1) for shape >= 1: Marsaglia and Tsang (2000), exact rejection from a transformed
// normal. Its cost does not grow with the shape.
double gamma_variate(Rng& rng, double shape);

// Beta(a, b), a, b >= 1: X / (X + Y), X ~ Gamma(a) drawn before Y ~ Gamma(b).
double beta_variate(Rng& rng, double a, double b);

// The ranks of a resample of n (> 0) ranks' order statistics: ranks_out[i] is the wanted[i]-th
// smallest (0-based) of n ranks drawn uniformly from {0, ..., n-1}. `wanted` strictly ascending, each < n;
// ranks_out as long as wanted. One Beta variate per wanted order statistic, in ascending order.
void resample_order_statistics(Rng& rng, std::size_t n, std::span<const std::size_t> wanted,
                               std::span<std::size_t> ranks_out);

}  // namespace m2mlat::stats
