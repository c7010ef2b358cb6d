// Politis-White block length: an autocorrelation screen, then flat-top spectral estimates.
#include "m2mlat/stats/block_length.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace m2mlat::stats {
namespace {

constexpr std::size_t kWhole = std::size_t{1} << 18;   // values used as they are
constexpr std::size_t kStretch = std::size_t{1} << 14;  // values a stretch of a longer series
constexpr std::size_t kStretches = 16;

// The autocovariances of the series' stretches about their common mean, computed lag by lag on demand.
class Autocovariance {
 public:
  explicit Autocovariance(std::span<const std::vector<double>> stretches) : stretches_(stretches) {
    double sum = 0;
    for (const auto& s : stretches_) {
      for (const double x : s) sum += x;
      used_ += s.size();
      shortest_ = std::min(shortest_, s.size());
    }
    mean_ = used_ == 0 ? 0.0 : sum / static_cast<double>(used_);
  }

  std::size_t used() const { return used_; }
  std::size_t longest_lag() const { return shortest_ - 1; }

  double at(std::size_t lag) {
    while (cache_.size() <= lag) {
      const std::size_t k = cache_.size();
      double sum = 0;
      for (const auto& s : stretches_)
        for (std::size_t t = 0; t + k < s.size(); ++t) sum += (s[t] - mean_) * (s[t + k] - mean_);
      cache_.push_back(sum / static_cast<double>(used_));
    }
    return cache_[lag];
  }

 private:
  std::span<const std::vector<double>> stretches_;
  std::size_t used_ = 0;
  std::size_t shortest_ = static_cast<std::size_t>(-1);
  double mean_ = 0;
  std::vector<double> cache_;
};

// The flat-top (trapezoid) lag window of Politis and Romano.
double flat_top(double t) {
  t = std::fabs(t);
  if (t <= 0.5) return 1.0;
  if (t <= 1.0) return 2.0 * (1.0 - t);
  return 0.0;
}

}  // namespace

std::vector<Stretch> estimation_stretches(std::size_t total) {
  if (total <= kWhole) return {{0, total}};
  std::vector<Stretch> out;
  const std::size_t step = (total - kStretch) / (kStretches - 1);
  for (std::size_t k = 0; k < kStretches; ++k) out.push_back({k * step, k * step + kStretch});
  return out;
}

BlockLength block_length(std::span<const double> series) {
  std::vector<std::vector<double>> stretches;
  for (const Stretch s : estimation_stretches(series.size()))
    stretches.emplace_back(series.begin() + static_cast<std::ptrdiff_t>(s.begin),
                           series.begin() + static_cast<std::ptrdiff_t>(s.end));
  return block_length(stretches, series.size());
}

BlockLength block_length(std::span<const std::vector<double>> stretches, std::size_t total) {
  BlockLength out;
  Autocovariance r(stretches);
  out.used = r.used();
  if (out.used < 8) return out;
  const double variance = r.at(0);
  if (!(variance > 0)) return out;
  const double n = static_cast<double>(r.used());
  const auto rho = [&](std::size_t k) { return r.at(k) / variance; };
  out.lag1 = rho(1);

  const auto runs = static_cast<std::size_t>(std::max(5.0, std::ceil(std::sqrt(std::log10(n)))));
  const std::size_t widest = std::min(static_cast<std::size_t>(std::ceil(std::sqrt(n))) + runs,
                                      r.longest_lag() - runs);
  const double band = 2.0 * std::sqrt(std::log10(n) / n);
  std::size_t reach = widest;
  for (std::size_t m = 0; m < widest; ++m) {
    bool inside = true;
    for (std::size_t k = 1; k <= runs && inside; ++k) inside = std::fabs(rho(m + k)) < band;
    if (inside) {
      reach = m;
      break;
    }
  }
  out.reach = reach;
  if (reach == 0) return out;

  const std::size_t window = std::min(2 * reach, widest);
  double g = 0, spectrum = r.at(0);  // G = sum lambda(k/M) |k| R(k); g(0) = sum lambda(k/M) R(k), k in -M..M
  for (std::size_t k = 1; k <= window; ++k) {
    const double w = flat_top(static_cast<double>(k) / static_cast<double>(window));
    g += 2.0 * w * static_cast<double>(k) * r.at(k);
    spectrum += 2.0 * w * r.at(k);
  }
  const double d = 4.0 / 3.0 * spectrum * spectrum;
  const double all = static_cast<double>(total);
  const double most = std::ceil(std::min(3.0 * std::sqrt(all), all / 3.0));
  const double b = d > 0 ? std::cbrt(2.0 * g * g / d) * std::cbrt(all) : most;
  out.length = static_cast<std::size_t>(std::clamp(std::round(b), 1.0, most));
  return out;
}

}  // namespace m2mlat::stats
