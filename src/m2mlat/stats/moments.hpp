// Mean and sample standard deviation of integer samples (latencies in ns), accurate for any n.
//
// Naive double summation of 10 million latencies of ~1e9 ns reaches 1e16, where a double's
// spacing is 2 ns, and loses up to ~n/2 ulp on the way. Here the sum is kept exactly in 128-bit
// two's complement (portable: two uint64 words, no compiler extension) and divided exactly into
// quotient and remainder, so the mean is within 1 ulp for any n; the standard deviation is a two-pass
// computation on deviations from that mean, taken in integers first so they stay exact even when the values
// are far from zero.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace m2mlat::stats {

// The exact sum of int64 values (up to 2^64 of them) in 128-bit two's complement.
class ExactSum {
 public:
  void add(std::int64_t value) {
    const auto u = static_cast<std::uint64_t>(value);
    low_ += u;
    high_ += (value < 0 ? ~std::uint64_t{0} : 0) + (low_ < u ? 1 : 0);
  }

  // sum = quotient * n + remainder with 0 <= remainder < n (floor division); n > 0. The
  // quotient must fit in int64, which holds whenever the sum is of at most n int64 values.
  struct Division {
    std::int64_t quotient = 0;
    std::uint64_t remainder = 0;
  };
  Division divide(std::uint64_t n) const;

  std::uint64_t high() const { return high_; }
  std::uint64_t low() const { return low_; }

 private:
  std::uint64_t high_ = 0;
  std::uint64_t low_ = 0;
};

// Mean and the pieces the second pass needs: mean = floor_ns + fraction with 0 <= fraction < 1.
struct Mean {
  double mean = 0.0;          // ns: floor_ns + fraction, rounded; NaN for n = 0
  std::int64_t floor_ns = 0;  // floor of the exact mean
  double fraction = 0.0;      // exact mean - floor_ns, rounded once
};
Mean exact_mean(std::span<const std::int64_t> values_ns);

// Sample standard deviation with divisor n - 1 (ns). NaN for n < 2. `mean` must be
// exact_mean(values_ns). Deviations x - mean are formed as (x - floor_ns) in integers, then minus
// the fraction, and the squares summed with compensation; the Chan-Golub-LeVeque correction
// removes what rounding of the mean leaves.
double sample_sd(std::span<const std::int64_t> values_ns, const Mean& mean);

}  // namespace m2mlat::stats
