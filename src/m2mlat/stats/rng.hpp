// A seeded pseudo-random generator that gives the same numbers on every platform and compiler.
//
// The bootstrap must be reproducible: the same seed gives the same confidence interval on a laptop
// and on an arm64 board. std::mt19937 is portable but the std:: distributions are not (each standard
// library maps raw bits to ranges in its own way), so m2mlat carries its own small generator:
// xoshiro256** (Blackman and Vigna) for the stream, splitmix64 to expand a 64-bit seed into its
// state, and Lemire's multiply-and-reject method for unbiased integers in [0, bound). All of it is
// integer arithmetic with defined results; no floating point decides which sample is drawn.
#pragma once

#include <cstdint>

#include "m2mlat/core/random.hpp"

namespace m2mlat::stats {

// splitmix64: a 64-bit counter passed through a mixing function. Used only to expand seeds.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t state) : state_(state) {}
  std::uint64_t next() { return core::splitmix64(state_); }

 private:
  std::uint64_t state_;
};

// The high and low 64-bit halves of the full 128-bit product a * b.
struct WideProduct {
  std::uint64_t high = 0;
  std::uint64_t low = 0;
};
// The same product from 32-bit halves only: the fallback where the compiler has no 128-bit type.
WideProduct multiply_wide_portable(std::uint64_t a, std::uint64_t b);
inline WideProduct multiply_wide(std::uint64_t a, std::uint64_t b) {
#if defined(__SIZEOF_INT128__)
  // One instruction on x86-64 and arm64; exactly the value multiply_wide_portable() computes.
  __extension__ using U128 = unsigned __int128;
  const U128 m = static_cast<U128>(a) * b;
  return {static_cast<std::uint64_t>(m >> 64), static_cast<std::uint64_t>(m)};
#else
  return multiply_wide_portable(a, b);
#endif
}

// xoshiro256**: period 2^256 - 1, 32 bytes of state, a few integer operations per number.
class Rng {
 public:
  // The state is four consecutive outputs of splitmix64 started at `seed`.
  explicit Rng(std::uint64_t seed);

  // Generator number `stream` of a family: its state is splitmix64 outputs 4*stream+1 ..
  // 4*stream+4 from `seed`, so the streams of one seed never share a state word and each can be
  // built directly (a parallel bootstrap can give every resample its own stream and still produce
  // the same numbers). Rng(seed) is stream 0.
  static Rng stream(std::uint64_t seed, std::uint64_t stream);

  std::uint64_t next() { return engine_.next(); }

  // Uniform integer in [0, bound), bound > 0, without modulo bias (Lemire 2019: the high half of
  // next() * bound, redrawn when the low half falls in the short, biased zone).
  std::uint64_t below(std::uint64_t bound);

  // Uniform double in [0, 1) with 53 random bits.
  double uniform01();

 private:
  explicit Rng(core::Xoshiro256 engine) : engine_(engine) {}
  core::Xoshiro256 engine_;
};

// A stream of uniform integers in [0, bound) for one fixed bound below 2^32: the bootstrap draws
// millions of ranks with the same bound. Each 64-bit output of the generator gives two 32-bit
// candidates, its high half first, then its low half; a candidate x becomes (x * bound) >> 32,
// and is skipped when the low 32 bits of x * bound fall below 2^32 mod bound (Lemire's
// rejection, so the result is exactly uniform). Half the generator calls of Rng::below().
class IndexStream {
 public:
  IndexStream(Rng rng, std::uint32_t bound);  // bound > 0

  std::uint32_t next() {
    for (;;) {
      std::uint32_t x;
      if (have_low_) {
        x = low_;
        have_low_ = false;
      } else {
        const std::uint64_t word = rng_.next();
        x = static_cast<std::uint32_t>(word >> 32);
        low_ = static_cast<std::uint32_t>(word);
        have_low_ = true;
      }
      const std::uint64_t m = std::uint64_t{x} * bound_;
      if (static_cast<std::uint32_t>(m) >= threshold_) return static_cast<std::uint32_t>(m >> 32);
    }
  }

 private:
  Rng rng_;
  std::uint64_t bound_;
  std::uint32_t threshold_;  // 2^32 mod bound
  std::uint32_t low_ = 0;    // the unused low half of the last output
  bool have_low_ = false;
};

}  // namespace m2mlat::stats
