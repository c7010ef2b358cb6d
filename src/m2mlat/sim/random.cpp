// Seeding of the simulator's streams and the variate transforms. See random.hpp.
#include "m2mlat/sim/random.hpp"

#include <array>
#include <cmath>  // sqrt: correctly rounded by IEEE-754, identical everywhere

#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/core/portable_math.hpp"

namespace m2mlat::sim {

Rng::Rng(std::uint64_t seed, std::uint64_t stream) {
  // Mix the stream number in through its own splitmix64 step so neighbouring streams are unrelated.
  std::uint64_t mix = stream;
  std::uint64_t state = seed ^ core::splitmix64(mix);
  core::Xoshiro256::State words;
  for (auto& word : words) word = core::splitmix64(state);
  if ((words[0] | words[1] | words[2] | words[3]) == 0) words[0] = 1;  // the all-zero state is a fixed point
  engine_ = core::Xoshiro256(words);
}

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

std::int64_t Rng::uniform_int(std::int64_t lo, std::int64_t hi) {
  const std::uint64_t range = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo) + 1;
  if (range == 0) return static_cast<std::int64_t>(next());  // the full 64-bit range
  // Reject the top partial block so every residue is equally likely.
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % range;
  std::uint64_t x = next();
  while (x >= limit) x = next();
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(lo) + x % range);
}

bool Rng::bernoulli(double p) { return uniform() < p; }

// Ziggurat method (Marsaglia and Tsang, 2000): the density is covered by N layers of equal area v,
// a rectangle each, with the tail beyond r folded into the bottom layer. A point falls inside the
// curve in most draws, which then cost one 64-bit number and a comparison; the rest are resolved
// exactly (wedge test or tail sampling), so the output is the exact distribution.
//
// x[i] is the right edge of layer i: x[0] = v / f(r) (bottom layer's equivalent width), x[1] = r,
// x[i+1] = f^-1(f(x[i]) + v / x[i]), x[N] = 0. The tables are computed once from portable_log and
// portable_exp, so they are identical everywhere.
namespace {
template <std::size_t N>
struct Ziggurat {
  std::array<double, N + 1> x{};
  std::array<double, N + 1> f{};  // f(x[i])
};

// Standard normal without its constant: f(x) = exp(-x^2 / 2), x >= 0. 128 layers.
const Ziggurat<128>& normal_ziggurat() {
  static const Ziggurat<128> z = [] {
    constexpr double r = 3.442619855899;
    constexpr double v = 9.91256303526217e-3;
    Ziggurat<128> t;
    t.x[0] = v / core::portable_exp(-0.5 * r * r);
    t.x[1] = r;
    for (std::size_t i = 1; i < 127; ++i)
      t.x[i + 1] =
          std::sqrt(-2.0 * core::portable_log(v / t.x[i] + core::portable_exp(-0.5 * t.x[i] * t.x[i])));
    t.x[128] = 0;
    for (std::size_t i = 0; i <= 128; ++i) t.f[i] = core::portable_exp(-0.5 * t.x[i] * t.x[i]);
    return t;
  }();
  return z;
}

// Exponential: f(x) = exp(-x), x >= 0. 256 layers.
const Ziggurat<256>& exponential_ziggurat() {
  static const Ziggurat<256> z = [] {
    constexpr double r = 7.69711747013104972;
    constexpr double v = 3.949659822581572e-3;
    Ziggurat<256> t;
    t.x[0] = v / core::portable_exp(-r);
    t.x[1] = r;
    for (std::size_t i = 1; i < 255; ++i)
      t.x[i + 1] = -core::portable_log(v / t.x[i] + core::portable_exp(-t.x[i]));
    t.x[256] = 0;
    for (std::size_t i = 0; i <= 256; ++i) t.f[i] = core::portable_exp(-t.x[i]);
    return t;
  }();
  return z;
}
}  // namespace

double Rng::normal() {
  const auto& z = normal_ziggurat();
  for (;;) {
    const std::uint64_t bits = next();
    const std::size_t i = bits & 127;                              // layer: 7 low bits
    const double sign = (bits & 128) ? -1.0 : 1.0;                 // 1 bit
    const double u = static_cast<double>(bits >> 11) * 0x1.0p-53;  // 53 high bits
    const double x = u * z.x[i];
    if (x < z.x[i + 1]) return sign * x;  // inside the layer's rectangle under the curve
    if (i == 0) {
      // The tail beyond r (Marsaglia, 1964): r + a with a ~ exp(r) restricted by a rejection test.
      for (;;) {
        const double a = -core::portable_log(1.0 - uniform()) / z.x[1];
        const double b = -core::portable_log(1.0 - uniform());
        if (2 * b > a * a) return sign * (z.x[1] + a);
      }
    }
    // The wedge: accept if a uniform height in the layer lies under the curve.
    if (z.f[i] + uniform() * (z.f[i + 1] - z.f[i]) < core::portable_exp(-0.5 * x * x)) return sign * x;
  }
}

double Rng::exponential() {
  const auto& z = exponential_ziggurat();
  double shift = 0;  // memorylessness: a tail draw is r + a fresh exponential
  for (;;) {
    const std::uint64_t bits = next();
    const std::size_t i = bits & 255;  // layer: 8 low bits
    const double u = static_cast<double>(bits >> 11) * 0x1.0p-53;
    const double x = u * z.x[i];
    if (x < z.x[i + 1]) return shift + x;
    if (i == 0) {
      shift += z.x[1];
      continue;
    }
    if (z.f[i] + uniform() * (z.f[i + 1] - z.f[i]) < core::portable_exp(-x)) return shift + x;
  }
}

}  // namespace m2mlat::sim
