// Sums and magnitudes of int64 nanoseconds that stop at the type's limits instead of overflowing
// (undefined behaviour). An error bound added up from what another program printed (chronyc, pmc)
// can be absurd; it must then stay an upper bound, never wrap to a small or negative one.
#pragma once

#include <cstdint>
#include <limits>

namespace m2mlat::core {

inline std::int64_t saturating_add(std::int64_t a, std::int64_t b) {
  std::int64_t sum = 0;
  if (__builtin_add_overflow(a, b, &sum))
    return b > 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
  return sum;
}

// |a|, with |INT64_MIN| given as INT64_MAX.
inline std::int64_t saturating_abs(std::int64_t a) {
  if (a == std::numeric_limits<std::int64_t>::min()) return std::numeric_limits<std::int64_t>::max();
  return a < 0 ? -a : a;
}

}  // namespace m2mlat::core
