// The simulator's pseudo-random numbers: core's xoshiro256** seeded through splitmix64, and the
// transforms to uniform, normal and exponential variates (ziggurat method, with tables computed by
// portable_math.hpp's functions). The std:: distributions are not used:
// their algorithms differ between standard libraries, so the same seed would give different rigs.
// Everything here is specified bit for bit and gives the same sequence on every platform.
#pragma once

#include <cstdint>

#include "m2mlat/core/random.hpp"

namespace m2mlat::sim {

// A generator for one concern of the simulation (the operator's manoeuvres, one sensor's bounces,
// one clock, ...). Separate streams keep concerns apart: changing the bounce probability does not
// move a single manoeuvre.
class Rng {
 public:
  // The stream `stream` of the simulation seeded with `seed`.
  Rng(std::uint64_t seed, std::uint64_t stream);

  // 64 uniformly distributed bits (xoshiro256**). Inline: every variate starts here.
  std::uint64_t next() { return engine_.next(); }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1), 53 random bits
  double uniform(double lo, double hi);                                       // [lo, hi)
  // Uniform integer in [lo, hi] (inclusive), without modulo bias. Requires lo <= hi.
  std::int64_t uniform_int(std::int64_t lo, std::int64_t hi);
  bool bernoulli(double p);  // true with probability p; always consumes one draw
  double normal();           // standard normal (ziggurat method, exact)
  double exponential();      // exponential with mean 1 (ziggurat method, exact)

 private:
  core::Xoshiro256 engine_;
};

}  // namespace m2mlat::sim
