// Seed expansion, the portable wide multiply and bounded draws of the platform-independent generator.
#include "m2mlat/stats/rng.hpp"

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

WideProduct multiply_wide_portable(std::uint64_t a, std::uint64_t b) {
  // Schoolbook multiplication on 32-bit digits; every partial sum fits in 64 bits.
  const std::uint64_t a_lo = a & 0xffffffffULL, a_hi = a >> 32;
  const std::uint64_t b_lo = b & 0xffffffffULL, b_hi = b >> 32;
  const std::uint64_t lo_lo = a_lo * b_lo;
  const std::uint64_t hi_lo = a_hi * b_lo;
  const std::uint64_t lo_hi = a_lo * b_hi;
  const std::uint64_t hi_hi = a_hi * b_hi;
  const std::uint64_t middle = (lo_lo >> 32) + (hi_lo & 0xffffffffULL) + lo_hi;
  return {hi_hi + (hi_lo >> 32) + (middle >> 32), (middle << 32) | (lo_lo & 0xffffffffULL)};
}

Rng::Rng(std::uint64_t seed) : Rng(stream(seed, 0)) {}

Rng Rng::stream(std::uint64_t seed, std::uint64_t stream) {
  // Skipping 4*stream outputs of splitmix64 is adding 4*stream increments to its counter.
  SplitMix64 expand(seed + 4 * stream * 0x9e3779b97f4a7c15ULL);
  core::Xoshiro256::State words;
  for (std::uint64_t& word : words) word = expand.next();
  // splitmix64 is a bijection of its counter, so the all-zero state (the one xoshiro must avoid)
  // needs four consecutive counters that all map to 0: impossible, as only one counter does.
  return Rng(core::Xoshiro256(words));
}

std::uint64_t Rng::below(std::uint64_t bound) {
  if (bound == 0) throw core::Error(core::ErrorKind::internal, "Rng::below: the bound must be positive");
  WideProduct m = multiply_wide(next(), bound);
  if (m.low < bound) {
    // 2^64 mod bound, computed in 64 bits as (2^64 - bound) mod bound.
    const std::uint64_t threshold = (0 - bound) % bound;
    while (m.low < threshold) m = multiply_wide(next(), bound);
  }
  return m.high;
}

double Rng::uniform01() {
  constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;
  return static_cast<double>(next() >> 11) * kTwoToMinus53;
}

IndexStream::IndexStream(Rng rng, std::uint32_t bound) : rng_(rng), bound_(bound), threshold_(0) {
  if (bound == 0) throw core::Error(core::ErrorKind::internal, "IndexStream: the bound must be positive");
  threshold_ = static_cast<std::uint32_t>((std::uint64_t{1} << 32) % bound);
}

}  // namespace m2mlat::stats
