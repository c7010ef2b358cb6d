// Resampled quantiles of a sorted sample from their order statistics' draws, and percentile
// intervals.
#include "m2mlat/stats/bootstrap.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/order_statistics.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/rng.hpp"

namespace m2mlat::stats {

void check_confidence_level(double level) {
  if (!(level > 0.0 && level < 1.0)) {
    throw core::Error(core::ErrorKind::usage, fmt::format("confidence level {} is outside (0, 1)", level));
  }
}

std::vector<double> BootstrapQuantiles::column(std::size_t k) const {
  std::vector<double> out(resamples);
  for (std::size_t b = 0; b < resamples; ++b) out[b] = value(b, k);
  return out;
}

BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed) {
  const std::size_t n = sorted_ns.size();
  if (n == 0) throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: empty sample");
  if (!std::is_sorted(sorted_ns.begin(), sorted_ns.end())) {
    throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: the sample is not sorted");
  }

  // The order statistics (0-based ranks within a resample) the quantiles interpolate between.
  std::vector<QuantilePosition> positions;
  std::vector<std::size_t> wanted;
  for (const double p : probabilities) {
    const QuantilePosition at = quantile_position(n, p);
    positions.push_back(at);
    wanted.push_back(at.lower);
    if (at.fraction != 0.0) wanted.push_back(at.lower + 1);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  const auto slot = [&](std::size_t rank) {
    return static_cast<std::size_t>(std::lower_bound(wanted.begin(), wanted.end(), rank) - wanted.begin());
  };

  BootstrapQuantiles out;
  out.probabilities.assign(probabilities.begin(), probabilities.end());
  out.resamples = resamples;
  out.values.resize(resamples * probabilities.size());
  std::vector<std::size_t> ranks(wanted.size());
  for (std::size_t b = 0; b < resamples; ++b) {
    Rng rng = Rng::stream(seed, b);
    resample_order_statistics(rng, n, wanted, ranks);
    for (std::size_t k = 0; k < positions.size(); ++k) {
      const QuantilePosition& at = positions[k];
      const std::int64_t low = sorted_ns[ranks[slot(at.lower)]];
      out.values[b * positions.size() + k] =
          at.fraction == 0.0 ? static_cast<double>(low)
                             : interpolate(low, sorted_ns[ranks[slot(at.lower + 1)]], at.fraction);
    }
  }
  return out;
}

Interval percentile_interval(std::span<const double> replicates, double level) {
  check_confidence_level(level);
  if (replicates.empty()) throw core::Error(core::ErrorKind::internal, "percentile_interval: no replicates");
  std::vector<double> sorted(replicates.begin(), replicates.end());
  std::sort(sorted.begin(), sorted.end());
  return {quantile(std::span<const double>(sorted), (1.0 - level) / 2.0),
          quantile(std::span<const double>(sorted), (1.0 + level) / 2.0)};
}

std::optional<MedianIqrCi> bootstrap_median_iqr(std::span<const std::int64_t> sorted_ns,
                                                const BootstrapOptions& options) {
  check_confidence_level(options.level);
  if (sorted_ns.empty() || options.resamples == 0) return std::nullopt;
  const double probabilities[] = {0.25, 0.5, 0.75};
  const BootstrapQuantiles q = bootstrap_quantiles(sorted_ns, probabilities, options.resamples, options.seed);
  std::vector<double> medians(q.resamples), iqrs(q.resamples);
  for (std::size_t b = 0; b < q.resamples; ++b) {
    medians[b] = q.value(b, 1);
    iqrs[b] = q.value(b, 2) - q.value(b, 0);
  }
  const auto to_ms = [](Interval i) { return Interval{i.lower / 1e6, i.upper / 1e6}; };
  MedianIqrCi ci;
  ci.median_ms = to_ms(percentile_interval(medians, options.level));
  ci.iqr_ms = to_ms(percentile_interval(iqrs, options.level));
  ci.resamples = options.resamples;
  ci.seed = options.seed;
  ci.level = options.level;
  return ci;
}

}  // namespace m2mlat::stats
