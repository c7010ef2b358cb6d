// Quantiles of the statistics' sample with the flagged pairs added or taken out, without a copy of it.
#include "m2mlat/analysis/flagged_effect.hpp"

#include <algorithm>
#include <limits>

#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

std::int64_t kth_value(std::span<const std::int64_t> sorted, std::span<const std::int64_t> other, bool add,
                       std::size_t k) {
  // The smallest v with more than k values at or below it, by bisection over the int64 values.
  const auto at_or_below = [&](std::int64_t v) {
    const auto a = static_cast<std::size_t>(std::upper_bound(sorted.begin(), sorted.end(), v) - sorted.begin());
    const auto b = static_cast<std::size_t>(std::upper_bound(other.begin(), other.end(), v) - other.begin());
    return add ? a + b : a - b;
  };
  std::int64_t lo = std::min(sorted.empty() ? std::numeric_limits<std::int64_t>::max() : sorted.front(),
                             other.empty() ? std::numeric_limits<std::int64_t>::max() : other.front());
  std::int64_t hi = std::max(sorted.empty() ? std::numeric_limits<std::int64_t>::min() : sorted.back(),
                             other.empty() ? std::numeric_limits<std::int64_t>::min() : other.back());
  while (lo < hi) {
    const auto width = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);  // no overflow
    const std::int64_t mid = lo + static_cast<std::int64_t>(width / 2);
    if (at_or_below(mid) > k)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

std::optional<FlaggedEffect> flagged_effect(std::span<const std::int64_t> statistics_sorted,
                                            std::span<const std::int64_t> flagged_sorted, bool included,
                                            const std::optional<stats::MedianIqrCi>& ci) {
  if (flagged_sorted.empty()) return std::nullopt;
  FlaggedEffect e;
  e.flagged = flagged_sorted.size();
  e.included = included;
  const std::size_t n = statistics_sorted.size();
  const std::size_t other_n = included ? n - flagged_sorted.size() : n + flagged_sorted.size();
  // The quantile at p of the statistics' own sample, or of the other one (flagged added or taken out), ns.
  const auto quantile = [&](bool own, double p) {
    if (own) return stats::quantile(statistics_sorted, p);
    const stats::QuantilePosition at = stats::quantile_position(other_n, p);
    const std::int64_t low = kth_value(statistics_sorted, flagged_sorted, !included, at.lower);
    if (at.fraction == 0.0) return static_cast<double>(low);
    return stats::interpolate(low, kth_value(statistics_sorted, flagged_sorted, !included, at.lower + 1),
                              at.fraction);
  };
  const auto fill = [&](bool own, double& median_ms, double& iqr_ms) {
    if ((own ? n : other_n) == 0) {
      median_ms = iqr_ms = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    median_ms = quantile(own, 0.5) / 1e6;
    iqr_ms = (quantile(own, 0.75) - quantile(own, 0.25)) / 1e6;
  };
  e.n_with = included ? n : other_n;
  e.n_without = included ? other_n : n;
  fill(included, e.median_with_ms, e.iqr_with_ms);
  fill(!included, e.median_without_ms, e.iqr_without_ms);
  if (ci) {
    e.half_median_ci_ms = ci->median_ms.width() / 2;
    e.half_iqr_ci_ms = ci->iqr_ms.width() / 2;
  }
  return e;
}

}  // namespace m2mlat::analysis
