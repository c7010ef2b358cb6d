// Bootstrap confidence intervals for quantiles (median, IQR), seeded and reproducible.
//
// Method (docs/statistics.md): nonparametric bootstrap with percentile intervals. Resample b
// (b = 0, 1, ..., B-1) is n draws with replacement from the SORTED sample; the statistic of a
// resample is computed from its type-7 quantiles, and the interval is the type-7 quantiles
// (1 - level)/2 and (1 + level)/2 of the B statistics. Only the resample's order statistics that
// the quantiles interpolate between are needed, and they are drawn directly from the stream
// Rng::stream(seed, b) (order_statistics.hpp: one Beta variate each, the resample's exact
// distribution), so a resample costs the same for 100 samples as for 10 million, and the same
// seed gives the same intervals on every platform.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace m2mlat::stats {

// Throws core::Error(usage) unless 0 < level < 1.
void check_confidence_level(double level);

struct BootstrapOptions {
  std::size_t resamples = 2000;  // B
  std::uint64_t seed = 1;        // same seed, same sample -> same intervals on every platform
  double level = 0.95;           // two-sided confidence level, in (0, 1)
};

// The resampled quantiles: value(b, k) is the type-7 quantile at probabilities[k] of resample b,
// in the unit of the sample (ns).
struct BootstrapQuantiles {
  std::vector<double> probabilities;
  std::size_t resamples = 0;
  std::vector<double> values;  // row-major: resamples x probabilities.size()

  double value(std::size_t resample, std::size_t k) const {
    return values[resample * probabilities.size() + k];
  }
  std::vector<double> column(std::size_t k) const;  // all resamples' values for probabilities[k]
};

// The bootstrap distribution of several quantiles at once (they share each resample, so a
// function of them, like q3 - q1, is resampled jointly). `sorted_ns` ascending and not empty;
// probabilities in [0, 1]. Throws core::Error(internal) on unsorted or empty input,
// core::Error(usage) on a bad probability.
BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed);

struct Interval {
  double lower = 0.0;
  double upper = 0.0;
  bool contains(double x) const { return lower <= x && x <= upper; }
  double width() const { return upper - lower; }
};

// Percentile interval: the type-7 quantiles (1 - level)/2 and (1 + level)/2 of `replicates`
// (sorts a copy). level in (0, 1); replicates not empty.
Interval percentile_interval(std::span<const double> replicates, double level);

struct MedianIqrCi {
  Interval median_ms;
  Interval iqr_ms;
  std::size_t resamples = 0;
  std::uint64_t seed = 0;
  double level = 0.0;
};

// Bootstrap CIs for the median and the IQR of a sorted sample (ns in, ms out). nullopt for an
// empty sample or resamples = 0.
std::optional<MedianIqrCi> bootstrap_median_iqr(std::span<const std::int64_t> sorted_ns,
                                                const BootstrapOptions& options = {});

}  // namespace m2mlat::stats
