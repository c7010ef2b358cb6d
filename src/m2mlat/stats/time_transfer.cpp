// ADEV, MDEV, TDEV and MTIE of a phase record (formulas in time_transfer.hpp).
#include "m2mlat/stats/time_transfer.hpp"

#include <cmath>
#include <deque>
#include <limits>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check(core::Duration tau0, std::size_t n) {
  if (n == 0)
    throw core::Error(core::ErrorKind::usage, "time-transfer metrics: averaging factor n must be >= 1");
  if (tau0.count() <= 0)
    throw core::Error(core::ErrorKind::usage,
                      "time-transfer metrics: the sample interval tau0 must be positive");
}

double second_difference(std::span<const double> x, std::size_t i, std::size_t n) {
  return x[i + 2 * n] - 2 * x[i + n] + x[i];
}

// MDEV^2 * tau^2 (ns^2): the modified Allan variance before its division by tau^2.
double mvar_tau2(std::span<const double> x, std::size_t n) {
  const std::size_t N = x.size();
  // Inner sums over a sliding window of n second differences, updated in O(1) per step.
  double inner = 0;
  for (std::size_t i = 0; i < n; ++i) inner += second_difference(x, i, n);
  double sum = inner * inner;
  const std::size_t last = N - 3 * n;  // j runs 0 .. last
  for (std::size_t j = 1; j <= last; ++j) {
    inner += second_difference(x, j + n - 1, n) - second_difference(x, j - 1, n);
    sum += inner * inner;
  }
  const auto nn = static_cast<double>(n);
  return sum / (2 * nn * nn * static_cast<double>(last + 1));
}

}  // namespace

double adev(std::span<const double> x_ns, core::Duration tau0, std::size_t n) {
  check(tau0, n);
  const std::size_t N = x_ns.size();
  if (N < 2 * n + 1) return kNaN;
  double sum = 0;
  for (std::size_t i = 0; i + 2 * n < N; ++i) {
    const double d = second_difference(x_ns, i, n);
    sum += d * d;
  }
  const double tau = static_cast<double>(n) * static_cast<double>(tau0.count());
  return std::sqrt(sum / (2 * static_cast<double>(N - 2 * n))) / tau;
}

double mdev(std::span<const double> x_ns, core::Duration tau0, std::size_t n) {
  check(tau0, n);
  if (x_ns.size() < 3 * n) return kNaN;
  const double tau = static_cast<double>(n) * static_cast<double>(tau0.count());
  return std::sqrt(mvar_tau2(x_ns, n)) / tau;
}

double tdev(std::span<const double> x_ns, core::Duration tau0, std::size_t n) {
  check(tau0, n);
  if (x_ns.size() < 3 * n) return kNaN;
  // tau / sqrt(3) * MDEV = sqrt(MVAR * tau^2 / 3): tau cancels.
  return std::sqrt(mvar_tau2(x_ns, n) / 3);
}

double mtie(std::span<const double> x_ns, std::size_t n) {
  if (n == 0)
    throw core::Error(core::ErrorKind::usage, "time-transfer metrics: averaging factor n must be >= 1");
  const std::size_t N = x_ns.size();
  if (N < n + 1) return kNaN;
  // Sliding window of n + 1 samples; monotone deques of indices hold the window's max and min.
  std::deque<std::size_t> hi, lo;
  double worst = 0;
  for (std::size_t i = 0; i < N; ++i) {
    while (!hi.empty() && x_ns[hi.back()] <= x_ns[i]) hi.pop_back();
    while (!lo.empty() && x_ns[lo.back()] >= x_ns[i]) lo.pop_back();
    hi.push_back(i);
    lo.push_back(i);
    if (i >= n) {
      const std::size_t first = i - n;  // the window is first .. i
      while (hi.front() < first) hi.pop_front();
      while (lo.front() < first) lo.pop_front();
      worst = std::max(worst, x_ns[hi.front()] - x_ns[lo.front()]);
    }
  }
  return worst;
}

std::vector<std::size_t> octave_factors(std::size_t samples, std::size_t limit) {
  std::vector<std::size_t> out;
  for (std::size_t n = 1; 2 * n + 1 <= samples && out.size() < limit; n *= 2) out.push_back(n);
  return out;
}

std::vector<StabilityPoint> stability(std::span<const double> x_ns, core::Duration tau0,
                                      std::span<const std::size_t> factors) {
  std::vector<StabilityPoint> out;
  out.reserve(factors.size());
  for (const std::size_t n : factors) {
    StabilityPoint p;
    p.n = n;
    p.tau_s = static_cast<double>(n) * static_cast<double>(tau0.count()) * 1e-9;
    p.adev = adev(x_ns, tau0, n);
    p.mdev = mdev(x_ns, tau0, n);
    p.tdev_ns = tdev(x_ns, tau0, n);
    p.mtie_ns = mtie(x_ns, n);
    p.adev_terms = x_ns.size() >= 2 * n + 1 ? x_ns.size() - 2 * n : 0;
    out.push_back(p);
  }
  return out;
}

}  // namespace m2mlat::stats
