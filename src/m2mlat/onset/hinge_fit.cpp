#include "m2mlat/onset/hinge_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace m2mlat::onset {

namespace {

// Solves the m x m system in `a` (column 3 the right-hand side) by Gaussian elimination with partial
// pivoting; false when singular.
bool solve(std::array<std::array<double, 5>, 4>& a, std::size_t m, std::array<double, 4>& x) {
  for (std::size_t c = 0; c < m; ++c) {
    std::size_t pivot = c;
    for (std::size_t r = c + 1; r < m; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    if (!(std::fabs(a[pivot][c]) > 0)) return false;
    std::swap(a[c], a[pivot]);
    for (std::size_t r = c + 1; r < m; ++r) {
      const double f = a[r][c] / a[c][c];
      for (std::size_t q = c; q < 5; ++q) a[r][q] -= f * a[c][q];
    }
  }
  for (std::size_t c = m; c-- > 0;) {
    double v = a[c][4];
    for (std::size_t q = c + 1; q < m; ++q) v -= a[c][q] * x[q];
    x[c] = v / a[c][c];
  }
  return true;
}

// The residual sum of squares of the best hinge at t0 = times[c].
class Profile {
 public:
  Profile(std::span<const std::int64_t> t, std::span<const double> p, bool rising)
      : t_(t), p_(p), dir_(rising ? 1 : -1) {
    for (const double v : p_) total_ += v * v, sum_ += v;
  }

  double sse(std::size_t c) const {
    const std::int64_t t0 = t_[c];
    // Sums over the samples on the moving side of t0 (tau in ms keeps them modest): s[k] = sum tau^k
    // (k = 1..8), b[k] = sum p tau^k (k = 1..4); s[0] and b[0] over the whole window (the rest level).
    std::array<double, 9> s{};
    std::array<double, 5> b{};
    s[0] = static_cast<double>(t_.size());
    b[0] = sum_;
    const std::size_t from = dir_ > 0 ? c + 1 : 0;
    const std::size_t to = dir_ > 0 ? t_.size() : c;
    for (std::size_t j = from; j < to; ++j) {
      const double tau = static_cast<double>(dir_ * (t_[j] - t0)) * 1e-6;
      double power = tau;
      for (std::size_t k = 1; k <= 8; ++k) {
        s[k] += power;
        if (k <= 4) b[k] += p_[j] * power;
        power *= tau;
      }
    }
    // Two shapes of start, each a physical one: a torque step (an actuator: the rate rises
    // linearly, c1 tau) and a smooth start (a hand: zero rate and acceleration at t0, c2 tau^2 +
    // c3 tau^3 + c4 tau^4, the start of any smooth rotation to fourth order). Mixing them
    // (c1 tau + c2 tau^2 + ...) leaves t0 a flat ridge of near-equal fits, so they are fitted apart
    // and the better kept, with c1, c2 >= 0 (the rate leaves rest upwards). gain = the sum of squares
    // the model explains.
    double gain = 0;
    // (The smooth start also as its sub-models, for when a larger one is not admissible.) Every model
    // has a rest level c0 of its own, fitted over the whole window: the detector's running estimate
    // has taken in a little of the motion's first, sub-threshold part.
    for (const unsigned mask : {0b00011u, 0b00101u, 0b01101u, 0b11101u}) {  // bit k: the term tau^k
      std::array<std::size_t, 4> powers{};
      std::size_t m = 0;
      for (std::size_t k = 0; k <= 4; ++k)
        if (mask & (1u << k)) powers[m++] = k;
      std::array<std::array<double, 5>, 4> a{};  // the normal equations, augmented
      for (std::size_t r = 0; r < m; ++r) {
        for (std::size_t q = 0; q < m; ++q) a[r][q] = s[powers[r] + powers[q]];
        a[r][4] = b[powers[r]];
      }
      std::array<double, 4> coef{};
      if (!solve(a, m, coef)) continue;
      bool admissible = true;
      for (std::size_t r = 0; r < m; ++r)
        if ((powers[r] == 1 || powers[r] == 2) && coef[r] < 0) admissible = false;
      if (!admissible) continue;
      double g = 0;
      for (std::size_t r = 0; r < m; ++r) g += coef[r] * b[powers[r]];
      gain = std::max(gain, g);
    }
    return total_ - gain;
  }

 private:
  std::span<const std::int64_t> t_;
  std::span<const double> p_;
  std::int64_t dir_;
  double total_ = 0, sum_ = 0;
};

// The lag-1 autocorrelation of the samples on the rest side of sample `best` (0 when too few),
// clamped to [0, 0.99].
double rest_correlation(std::span<const double> p, std::size_t best, bool rising) {
  const auto rest = rising ? p.first(best) : p.subspan(best + 1);
  if (rest.size() < 16) return 0;
  double mean = 0;
  for (const double v : rest) mean += v;
  mean /= static_cast<double>(rest.size());
  double lag0 = 0, lag1 = 0;
  for (std::size_t j = 0; j < rest.size(); ++j) {
    lag0 += (rest[j] - mean) * (rest[j] - mean);
    if (j > 0) lag1 += (rest[j] - mean) * (rest[j - 1] - mean);
  }
  return lag0 > 0 ? std::clamp(lag1 / lag0, 0.0, 0.99) : 0.0;
}

}  // namespace

HingeFit fit_hinge(std::span<const std::int64_t> times_ns, std::span<const double> p, bool rising) {
  HingeFit fit;
  const std::size_t n = std::min(times_ns.size(), p.size());
  if (n < 8) return fit;
  const Profile profile(times_ns.first(n), p.first(n), rising);

  // A coarse scan, then finer ones (each an eighth of the last step) around the best point, down to
  // every sample: about 100 evaluations for any window.
  std::size_t stride = std::max<std::size_t>(1, n / 64);
  std::size_t best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < n; c += stride) {
    const double v = profile.sse(c);
    if (v < best_sse) best_sse = v, best = c;
  }
  for (std::size_t step = stride; step > 1;) {
    const std::size_t finer = std::max<std::size_t>(1, step / 8);
    const std::size_t lo = best > 2 * step ? best - 2 * step : 0;
    const std::size_t hi = std::min(n - 1, best + 2 * step);
    for (std::size_t c = lo; c <= hi; c += finer) {
      const double v = profile.sse(c);
      if (v < best_sse) best_sse = v, best = c;
    }
    step = finer;
  }

  // Between samples: the vertex of the parabola through the best point and its neighbours.
  double t0 = static_cast<double>(times_ns[best] - times_ns[0]);
  double curvature = 0;  // of the residual sum of squares at its minimum, per ns^2 (0: unknown)
  if (best > 0 && best + 1 < n) {
    const double xa = static_cast<double>(times_ns[best - 1] - times_ns[0]);
    const double xc = static_cast<double>(times_ns[best + 1] - times_ns[0]);
    const double ya = profile.sse(best - 1), yb = best_sse, yc = profile.sse(best + 1);
    const double xb = t0;
    const double den = (xa - xb) * (xa - xc) * (xb - xc);
    const double a = (xc * (yb - ya) + xb * (ya - yc) + xa * (yc - yb)) / den;
    const double b = (xc * xc * (ya - yb) + xb * xb * (yc - ya) + xa * xa * (yb - yc)) / den;
    if (a > 0) t0 = std::clamp(-b / (2 * a), xa, xc), curvature = a;
  }
  fit.t0_ns = times_ns[0] + std::llround(t0);

  // The interval where the residual sum of squares stays within one residual variance of the best:
  // scanned sample by sample, and from the parabola's curvature (for an interval narrower than a
  // sample); the wider is taken.
  const double variance = best_sse / static_cast<double>(n - 5);  // t0, the rest level, up to 3 terms
  const double limit = best_sse + variance;
  auto edge = [&](int step_sign) {
    std::size_t c = best;
    for (int steps = 0;; ++steps) {
      const std::size_t step = steps < 64 ? 1 : stride;
      if (step_sign < 0 ? c < step : c + step >= n) return c;
      const std::size_t next = step_sign < 0 ? c - step : c + step;
      if (profile.sse(next) > limit) return c;
      c = next;
    }
  };
  const std::size_t left = edge(-1), right = edge(+1);
  const double spacing = static_cast<double>(times_ns[n - 1] - times_ns[0]) / static_cast<double>(n - 1);
  const double half = std::max(static_cast<double>(times_ns[right] - times_ns[left]) / 2,
                               curvature > 0 ? std::sqrt(variance / curvature) : 0.0);
  // That interval assumes independent samples; a chip's filter makes neighbours alike, which the rest
  // side of the window shows: with its lag-1 correlation rho, the interval widens by
  // sqrt((1 + rho) / (1 - rho)) (the variance of a mean of AR(1) noise).
  const double rho = rest_correlation(p.first(n), best, rising);
  const double widen = std::sqrt((1 + rho) / (1 - rho));
  fit.sd_ns = std::max(half * widen, spacing / std::sqrt(12.0));
  fit.valid = true;
  return fit;
}

}  // namespace m2mlat::onset
