// The pseudo-random engine shared by the simulator and the statistics: xoshiro256** (Blackman and
// Vigna, 2018) with splitmix64 (Steele, Lea and Flood) to expand seeds, written from their published
// definitions. Integer arithmetic only, so a seed gives the same numbers on every platform and
// compiler (the std:: distributions do not: each standard library maps bits to ranges its own way).
// How a seed becomes a state, and how bits become variates, is each user's own (sim/random.hpp,
// stats/rng.hpp).
#pragma once

#include <array>
#include <cstdint>

namespace m2mlat::core {

// One step of splitmix64: advances `state` by the golden-ratio increment and returns its mix.
inline std::uint64_t splitmix64(std::uint64_t& state) {
  state += 0x9e3779b97f4a7c15ULL;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// xoshiro256**: period 2^256 - 1, 32 bytes of state. The state must not be all zero.
class Xoshiro256 {
 public:
  using State = std::array<std::uint64_t, 4>;
  constexpr Xoshiro256() = default;
  explicit constexpr Xoshiro256(const State& state) : s_(state) {}

  // 64 uniformly distributed bits.
  constexpr std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  State s_{1, 0, 0, 0};
};

}  // namespace m2mlat::core
