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
//
// Samples that are not independent (the pairs of one manoeuvre share its network and actuator
// delay; a link's latency wanders) are resampled as they arose: resample_median_iqr takes the sample
// in time order with the units it came in (manoeuvres), and resamples whole units, in circular
// blocks of consecutive units when the units' latencies are themselves correlated (block_length.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "m2mlat/stats/block_length.hpp"

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

// Samples above this many are resampled one by one even where they came in units or are correlated:
// the units' bootstrap walks the whole sample once a resample (2000 x 2^20 steps, a few seconds), and
// its labelled copy costs 16 bytes a sample. Resampling::over_limit says so wherever the CI is shown.
inline constexpr std::size_t kMaxUnitResampled = std::size_t{1} << 20;

// What a bootstrap resampled: units (each a run of consecutive samples) in blocks of consecutive units.
struct Resampling {
  std::size_t samples = 0;       // values in the sample
  std::size_t units = 0;         // units (samples, when each is its own unit)
  std::size_t largest_unit = 1;  // samples in the largest unit
  BlockLength blocks;            // of the units' latencies: blocks.length units are drawn together
  bool over_limit = false;       // grouped or correlated, but above kMaxUnitResampled: sample by sample
  bool grouped() const { return largest_unit > 1; }
  // Each sample drawn on its own: the plain bootstrap of bootstrap_median_iqr.
  bool sample_by_sample() const { return over_limit || (!grouped() && blocks.length == 1); }
};

struct MedianIqrCi {
  Interval median_ms;
  Interval iqr_ms;
  std::size_t resamples = 0;
  std::uint64_t seed = 0;
  double level = 0.0;
  Resampling resampling;  // samples on their own unless resample_median_iqr found otherwise
};

// Bootstrap CIs for the median and the IQR of a sorted sample (ns in, ms out). nullopt for an
// empty sample or resamples = 0.
std::optional<MedianIqrCi> bootstrap_median_iqr(std::span<const std::int64_t> sorted_ns,
                                                const BootstrapOptions& options = {});

// How a sample in time order (`in_time_order`, ns) with its units should be resampled. `unit_starts`
// are the ascending positions where each unit begins (the first 0), or empty: every sample its own
// unit. The blocks are chosen on the ranks of the units' mean latencies, so that a few stalls do not
// decide them. Throws core::Error(internal) on unit starts that are not ascending within the sample.
Resampling plan_resampling(std::span<const std::int64_t> in_time_order, std::span<const std::size_t> unit_starts);

// The replicates of a units' bootstrap (plan not sample by sample): per resample its type-7 quartiles
// (ns) and, with_sd, its standard deviation (ms, n - 1). Resample b draws from Rng::stream(seed, b).
struct UnitReplicates {
  std::vector<double> q1, median, q3, sd_ms;
};
UnitReplicates unit_replicates(std::span<const std::int64_t> in_time_order, std::span<const std::size_t> unit_starts,
                               const Resampling& plan, std::size_t resamples, std::uint64_t seed, bool with_sd);

// The median's and IQR's CIs resampling as `plan` says: each resample draws circular blocks of
// plan.blocks.length consecutive units (block starts uniform, Politis and Romano 1992) until it holds
// as many units as the sample, and takes the type-7 quantiles of the samples they hold. A plan sample by
// sample gives exactly bootstrap_median_iqr's intervals. nullopt for an empty sample or resamples = 0.
std::optional<MedianIqrCi> resample_median_iqr(std::span<const std::int64_t> in_time_order,
                                               std::span<const std::size_t> unit_starts, const Resampling& plan,
                                               const BootstrapOptions& options = {});

}  // namespace m2mlat::stats
