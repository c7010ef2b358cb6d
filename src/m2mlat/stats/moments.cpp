// Exact 128-bit summation and division for the mean; the two-pass standard deviation.
#include "m2mlat/stats/moments.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

namespace {

// A 128-bit magnitude divided by a 64-bit divisor, bit by bit (runs once per summary: 128 steps).
struct Unsigned128 {
  std::uint64_t high = 0;
  std::uint64_t low = 0;
};

void divide_magnitude(Unsigned128 value, std::uint64_t divisor, Unsigned128& quotient,
                      std::uint64_t& remainder) {
  quotient = {};
  std::uint64_t rem = 0;
  for (int bit = 127; bit >= 0; --bit) {
    const std::uint64_t next_bit = bit >= 64 ? (value.high >> (bit - 64)) & 1 : (value.low >> bit) & 1;
    // rem < divisor <= 2^64 - 1; shifting in one bit may carry out of 64 bits.
    const bool carry = (rem >> 63) != 0;
    rem = (rem << 1) | next_bit;
    if (carry || rem >= divisor) {
      rem -= divisor;  // wraps correctly when carry is set: the true value is rem + 2^64 - divisor
      if (bit >= 64) {
        quotient.high |= std::uint64_t{1} << (bit - 64);
      } else {
        quotient.low |= std::uint64_t{1} << bit;
      }
    }
  }
  remainder = rem;
}

// Neumaier's compensated sum: the error of each addition is carried along and added at the end.
class CompensatedSum {
 public:
  void add(double x) {
    const double t = sum_ + x;
    if (std::fabs(sum_) >= std::fabs(x)) {
      compensation_ += (sum_ - t) + x;
    } else {
      compensation_ += (x - t) + sum_;
    }
    sum_ = t;
  }
  double value() const { return sum_ + compensation_; }

 private:
  double sum_ = 0.0;
  double compensation_ = 0.0;
};

}  // namespace

ExactSum::Division ExactSum::divide(std::uint64_t n) const {
  if (n == 0) throw core::Error(core::ErrorKind::internal, "ExactSum::divide: division by zero");
  const bool negative = (high_ >> 63) != 0;
  Unsigned128 magnitude{high_, low_};
  if (negative) {  // two's complement negation of the 128-bit value
    magnitude.low = ~low_ + 1;
    magnitude.high = ~high_ + (magnitude.low == 0 ? 1 : 0);
  }
  Unsigned128 q;
  std::uint64_t r = 0;
  divide_magnitude(magnitude, n, q, r);
  // |sum| = q n + r. For a negative sum, floor division gives -(q + 1) remainder n - r unless r = 0.
  if (negative && r != 0) {
    q.low += 1;
    if (q.low == 0) q.high += 1;
    r = n - r;
  }
  constexpr std::uint64_t kInt64Magnitude = std::uint64_t{1} << 63;  // |INT64_MIN|
  if (q.high != 0 || q.low > kInt64Magnitude || (!negative && q.low == kInt64Magnitude)) {
    throw core::Error(core::ErrorKind::internal, "ExactSum::divide: quotient outside int64");
  }
  Division result;
  result.quotient = negative ? static_cast<std::int64_t>(0 - q.low) : static_cast<std::int64_t>(q.low);
  result.remainder = r;
  return result;
}

Mean exact_mean(std::span<const std::int64_t> values_ns) {
  Mean result;
  if (values_ns.empty()) {
    result.mean = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  ExactSum sum;
  for (const std::int64_t v : values_ns) sum.add(v);
  const ExactSum::Division d = sum.divide(values_ns.size());
  result.floor_ns = d.quotient;
  result.fraction = static_cast<double>(d.remainder) / static_cast<double>(values_ns.size());
  result.mean = static_cast<double>(d.quotient) + result.fraction;
  return result;
}

double sample_sd(std::span<const std::int64_t> values_ns, const Mean& mean) {
  const std::size_t n = values_ns.size();
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  CompensatedSum squares, deviations;
  for (const std::int64_t v : values_ns) {
    // v - floor_ns in integers is exact unless it leaves int64 (a spread of 292 years); then
    // fall back to doubles, which is still accurate to a relative 1e-16 at such distances.
    const auto a = static_cast<std::uint64_t>(v), b = static_cast<std::uint64_t>(mean.floor_ns);
    const std::uint64_t diff = a - b;
    const bool overflow = (((a ^ b) & (a ^ diff)) >> 63) != 0;
    const double dev = overflow ? static_cast<double>(v) - mean.mean
                                : static_cast<double>(static_cast<std::int64_t>(diff)) - mean.fraction;
    squares.add(dev * dev);
    deviations.add(dev);
  }
  const double dev_sum = deviations.value();
  const double ss = squares.value() - dev_sum * dev_sum / static_cast<double>(n);
  return std::sqrt(std::max(ss, 0.0) / static_cast<double>(n - 1));
}

}  // namespace m2mlat::stats
