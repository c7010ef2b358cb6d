// Logarithm, exponential and cosine from basic IEEE operations (see portable_math.hpp for why).
#include "m2mlat/core/portable_math.hpp"

#include <array>
#include <bit>
#include <cmath>  // ldexp and floor only: exact operations, identical everywhere
#include <cstdint>

#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly

namespace m2mlat::core {

namespace {
// ln 2 split so that k * kLn2High is exact for |k| < 2^11 (Cody and Waite's argument reduction).
constexpr double kLn2High = 0x1.62e42fee00000p-1;
constexpr double kLn2Low = 0x1.a39ef35793c76p-33;
constexpr double kInvLn2 = 1.44269504088896340735992468100189214;
constexpr double kSqrtTwo = 1.41421356237309504880168872420969808;

// 1 / (2k + 1), k = 0..10, and 1 / n!, n = 0..17: computed at compile time, the same everywhere.
constexpr std::array<double, 11> kOddInverse = [] {
  std::array<double, 11> c{};
  for (std::size_t k = 0; k < c.size(); ++k) c[k] = 1.0 / static_cast<double>(2 * k + 1);
  return c;
}();
constexpr std::array<double, 18> kInverseFactorial = [] {
  std::array<double, 18> c{};
  double factorial = 1;  // exact: 17! < 2^53, so each entry is one correctly rounded division
  for (std::size_t n = 0; n < c.size(); ++n) {
    if (n > 0) factorial *= static_cast<double>(n);
    c[n] = 1.0 / factorial;
  }
  return c;
}();
// 2 pi split so that k * kTwoPiHigh is exact for |k| < 2^20; 1 / (2n)!, n = 0..16.
constexpr double kTwoPiHigh = 0x1.921fb544p+2;
constexpr double kTwoPiLow = 0x1.0b4611a626331p-32;
constexpr double kInvTwoPi = 0.159154943091895335768883763372514362;
constexpr std::array<double, 17> kInverseEvenFactorial = [] {
  std::array<double, 17> c{};
  double factorial = 1;  // (2n)! rounded once per step: the same everywhere (compile time)
  for (std::size_t n = 0; n < c.size(); ++n) {
    if (n > 0) factorial *= static_cast<double>((2 * n - 1) * (2 * n));
    c[n] = 1.0 / factorial;
  }
  return c;
}();
}  // namespace

double portable_log(double x) {
  if (!(x > 0)) return -std::numeric_limits<double>::infinity();
  if (x == std::numeric_limits<double>::infinity()) return x;
  // Split x = m * 2^exponent with m in [sqrt(1/2), sqrt(2)) by taking the bits apart (exact).
  auto bits = std::bit_cast<std::uint64_t>(x);
  int exponent = 0;
  if ((bits >> 52) == 0) {  // subnormal: scale into the normal range first
    bits = std::bit_cast<std::uint64_t>(x * 0x1.0p54);
    exponent = -54;
  }
  exponent += static_cast<int>(bits >> 52) - 1023;
  double m = std::bit_cast<double>((bits & 0x000f'ffff'ffff'ffffULL) | 0x3ff0'0000'0000'0000ULL);  // [1, 2)
  if (m >= kSqrtTwo) {
    m *= 0.5;
    ++exponent;
  }
  // log(m) = 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...), s = (m-1)/(m+1), |s| < 0.172, s^2 < 0.0295;
  // eleven terms leave a relative error below 0.0295^11 / 23 < 1e-18.
  const double s = (m - 1) / (m + 1);
  const double s2 = s * s;
  double series = kOddInverse[10];
  for (int k = 9; k >= 0; --k) series = kOddInverse[k] + s2 * series;
  const double e = exponent;
  return e * kLn2High + (e * kLn2Low + 2 * s * series);
}

double portable_exp(double x) {
  if (x != x) return x;
  if (x > 709.8) return std::numeric_limits<double>::infinity();
  if (x < -745.2) return 0.0;
  // x = k ln2 + r with |r| <= ln2/2; e^x = 2^k e^r, e^r by its Taylor series (17 terms: < 1e-19).
  const double k = std::floor(x * kInvLn2 + 0.5);
  const double r = (x - k * kLn2High) - k * kLn2Low;
  double sum = kInverseFactorial[17];
  for (int n = 16; n >= 0; --n) sum = kInverseFactorial[n] + r * sum;
  return std::ldexp(sum, static_cast<int>(k));
}

double portable_cos(double x) {
  if (x != x) return x;
  // x = k 2pi + y with |y| <= pi; cos y by its Taylor series (17 terms: pi^34 / 34! < 1e-20).
  const double k = std::floor(x * kInvTwoPi + 0.5);
  const double y = (x - k * kTwoPiHigh) - k * kTwoPiLow;
  const double y2 = y * y;
  double sum = kInverseEvenFactorial[16];
  for (int n = 15; n >= 0; --n) sum = kInverseEvenFactorial[static_cast<std::size_t>(n)] - y2 * sum;
  return sum;
}

}  // namespace m2mlat::core
