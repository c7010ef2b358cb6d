// A local-level Kalman filter and its step GLR (model in kernel_log_fine_steps.hpp). Inside the
// model the values are doubles in us and s; what leaves it is int64 ns.
#include "m2mlat/analysis/kernel_log_fine_steps.hpp"

#include <algorithm>
#include <cmath>

#include "m2mlat/stats/distributions.hpp"

namespace m2mlat::analysis {

namespace {

struct Filtered {
  std::vector<double> nu, f, gain;  // per line: innovation (us), its variance (us^2), Kalman gain
  double loglik = 0;
};

// The local level through lines [0, n): t in s, y in us.
Filtered filter(std::span<const double> t, std::span<const double> y, double q, double r, std::size_t n) {
  Filtered out;
  out.nu.assign(n, 0);
  out.f.assign(n, 1);
  out.gain.assign(n, 1);
  double level = y[0], p = 4 * r;
  for (std::size_t k = 1; k < n; ++k) {
    const double predicted = p + q * std::max(t[k] - t[k - 1], 1e-6);
    const double f = predicted + r;
    const double v = y[k] - level;
    const double gain = predicted / f;
    level += gain * v;
    p = (1 - gain) * predicted;
    out.nu[k] = v;
    out.f[k] = f;
    out.gain[k] = gain;
    out.loglik += -0.5 * std::log(f) - 2.5 * std::log1p(v * v / (4 * f));  // Student-t, 4 degrees of freedom
  }
  return out;
}

double median_of(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

FineSteps fine_steps(std::span<const std::int64_t> mono_ns, std::span<const std::int64_t> d_ns,
                     const FineStepOptions& options) {
  FineSteps result;
  auto& out = result.steps;
  const std::size_t n = std::min(mono_ns.size(), d_ns.size());
  const std::size_t horizon = std::max<std::size_t>(options.horizon, 2);
  if (n < 2 * horizon) return result;
  // Detrended by the median rate between lines (robust to the steps themselves: one gap each).
  std::vector<double> t(n), y(n);
  std::vector<double> rates;
  for (std::size_t i = 0; i < n; ++i) t[i] = static_cast<double>(mono_ns[i] - mono_ns[0]) * 1e-9;
  for (std::size_t i = 1; i < n; ++i)
    if (t[i] > t[i - 1]) rates.push_back(static_cast<double>(d_ns[i] - d_ns[i - 1]) * 1e-3 / (t[i] - t[i - 1]));
  if (rates.size() < horizon) return result;
  const double rate = median_of(rates);  // us/s
  for (std::size_t i = 0; i < n; ++i) y[i] = static_cast<double>(d_ns[i] - d_ns[0]) * 1e-3 - rate * t[i];

  // q (us^2/s) and r (us^2): the grid's most likely pair.
  const std::size_t fit_n = std::min<std::size_t>(n, 4096);
  double q = 1, r = 1, best = -INFINITY;
  for (int lq = -4; lq <= 17; ++lq)
    for (int lr = 0; lr <= 16; ++lr) {
      const double qq = std::pow(10.0, 0.5 * lq), rr = std::pow(10.0, 0.5 * lr);
      const double ll = filter(t, y, qq, rr, fit_n).loglik;
      if (ll > best) best = ll, q = qq, r = rr;
    }

  // Slewing: two gaps in a row moving the same way faster than half the bound, beyond the noise.
  std::vector<bool> slewing(n, false);
  {
    std::vector<int> fast(n, 0);
    for (std::size_t i = 1; i < n; ++i) {
      const double tau = t[i] - t[i - 1];
      const double move = y[i] - y[i - 1] + rate * tau;  // d's own move, us
      const double limit = options.slew_ppm / 2 * tau + 3 * std::sqrt(2 * r + q * tau);
      if (std::fabs(move) > limit) fast[i] = move > 0 ? 1 : -1;
    }
    for (std::size_t i = 2; i < n; ++i)
      if (fast[i] != 0 && fast[i] == fast[i - 1]) {
        const std::size_t from = i >= 1 + horizon ? i - 1 - horizon : 0;
        for (std::size_t k = from; k < std::min(n, i + horizon); ++k) slewing[k] = true;
      }
  }

  const double z = stats::normal_quantile(1 - options.alpha / (2.0 * static_cast<double>(n)));
  const double critical = z * z;
  const double min_size_us = static_cast<double>(options.min_size_ns) * 1e-3;
  for (std::size_t found = 0; found < options.max_steps; ++found) {
    const auto f = filter(t, y, q, r, n);
    double best_chi = 0, best_size = 0, best_sd = 0;
    std::size_t best_line = 0;
    std::vector<double> sds;  // a unit step's standard deviation per line (the first search's)
    for (std::size_t g = 2; g + 1 < n; ++g) {
      if (slewing[g]) continue;
      // The innovations' response to a unit step (mu) and to a unit change of rate (ramp) at g.
      double step_bias = 0, ramp_bias = 0, a = 0, b = 0, ar = 0, br = 0;
      for (std::size_t k = g; k < std::min(n, g + horizon); ++k) {
        const double mu = 1 - step_bias;
        const double ramp = (t[k] - t[g - 1]) - ramp_bias;
        a += mu * f.nu[k] / f.f[k];
        b += mu * mu / f.f[k];
        ar += ramp * f.nu[k] / f.f[k];
        br += ramp * ramp / f.f[k];
        step_bias += f.gain[k] * mu;
        ramp_bias += f.gain[k] * ramp;
      }
      if (found == 0) sds.push_back(1 / std::sqrt(b));
      const double chi = a * a / b;
      if (chi <= best_chi || (br > 0 && chi <= ar * ar / br)) continue;
      best_chi = chi;
      best_size = a / b;
      best_sd = 1 / std::sqrt(b);
      best_line = g;
    }
    if (found == 0 && !sds.empty()) result.floor_ns = std::llround((z + 1.645) * median_of(std::move(sds)) * 1e3);
    if (best_line == 0 || best_chi < critical || std::fabs(best_size) < min_size_us) break;
    out.push_back({best_line, std::llround(best_size * 1e3), std::llround(best_sd * 1e3)});
    for (std::size_t k = best_line; k < n; ++k) y[k] -= best_size;
  }
  std::sort(out.begin(), out.end(), [](const FineStep& a, const FineStep& b) { return a.line < b.line; });
  return result;
}

}  // namespace m2mlat::analysis
