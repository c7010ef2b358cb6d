// Bootstrap confidence intervals for quantiles (median, IQR), seeded and reproducible.
//
// Method (docs/statistics.md): nonparametric bootstrap with percentile intervals. Resample b
// (b = 0, 1, ..., B-1) draws n ranks uniformly with replacement from the SORTED sample, from
// IndexStream(Rng::stream(seed, b), n). Its order statistics are read from the counts of each
// rank, so no resample is ever sorted: element j (0-based) of the sorted resample is sorted[r]
// for the smallest r whose cumulative count exceeds j. That is O(n) per resample, exact (the
// same values as sorting the resample), and integer arithmetic only, so every platform draws
// the same resamples. The statistic of a resample is computed from its type-7 quantiles; the
// interval is the type-7 quantiles (1 - level)/2 and (1 + level)/2 of the B statistics.
//
// Cost: about n * B draws at ~1 ns each (measured on x86-64), i.e. 2 s for n = 1e7 with
// B = 200. B = 2000 suits samples up to ~1e6; for 1e7 samples choose B of a few hundred.
// Large bootstraps (n * B >= 2^24) share the resamples among up to four threads, one a core;
// the result does not depend on the number of threads (each resample has its own stream).
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

namespace detail {
// How resample order statistics are counted; both give identical results (bootstrap.cpp).
// Exposed for tests and measurements: automatic picks windowed when the windows cover at most
// an eighth of the sample. half_width 0 means 3 ceil(sqrt(n)) + 32 ranks either side of each
// wanted order statistic. `fallbacks`, if given, receives the number of resamples that fell
// outside the windows and were counted in full. `threads` 0 means bootstrap_threads(n, B).
enum class RankCounting { automatic, full, windowed };
BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed, RankCounting how, std::size_t half_width = 0,
                                       std::size_t* fallbacks = nullptr, std::size_t threads = 0);

// Threads for n samples and B resamples: 1 below 2^24 draws, else one a core, at most
// kMaxBootstrapThreads (each thread has its own counts: up to 4 n bytes with full counting).
inline constexpr std::size_t kMaxBootstrapThreads = 4;
std::size_t bootstrap_threads(std::size_t n, std::size_t resamples);
}  // namespace detail

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
