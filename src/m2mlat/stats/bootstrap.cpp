// Resampling ranks of a sorted sample, reading order statistics from rank counts, and
// percentile intervals.
#include "m2mlat/stats/bootstrap.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <system_error>
#include <thread>

#include "m2mlat/core/error.hpp"
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

namespace {

// Reads order statistics of one resample from counts of how often each rank of the sorted
// sample was drawn. Element j (0-based) of the sorted resample is sorted[r] for the first r
// whose cumulative count exceeds j.
//
// Full counting keeps one count per rank: simple, but for millions of samples every draw is a
// cache miss. Windowed counting keeps one count per bucket of 2^shift consecutive ranks, and
// per-rank counts only in the buckets near the wanted order statistics: element j of a
// resample lies within a few sqrt(n) of rank j (the number of draws below a rank is binomial,
// standard deviation <= sqrt(n)/2). Both arrays stay in the cache. If an order statistic falls
// in a bucket without per-rank counts (a 6-sigma event with the default width), that resample
// is drawn again from the same stream and counted in full, so the result is always exactly
// that of full counting.
class RankCounter {
 public:
  RankCounter(std::span<const std::int64_t> sorted, std::span<const std::size_t> wanted,
              detail::RankCounting how, std::size_t half_width)
      : sorted_(sorted), wanted_(wanted) {
    const std::size_t n = sorted.size();
    if (half_width == 0)
      half_width = 3 * static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n)))) + 32;
    // Buckets of about a quarter of the half-width: windows then waste little beyond +-half_width.
    while (shift_ < 20 && (std::size_t{2} << shift_) <= std::max<std::size_t>(half_width / 4, 64)) ++shift_;
    const std::size_t buckets = ((n - 1) >> shift_) + 1;
    std::vector<bool> fine(buckets, false);
    for (const std::size_t j : wanted) {
      const std::size_t first = (j > half_width ? j - half_width : 0) >> shift_;
      const std::size_t last = std::min(n - 1, j + half_width) >> shift_;
      for (std::size_t b = first; b <= last; ++b) fine[b] = true;
    }
    fine_offset_.assign(buckets, kNoFine);
    std::size_t covered = 0;
    for (std::size_t b = 0; b < buckets; ++b) {
      if (fine[b]) {
        fine_offset_[b] = covered;
        covered += std::size_t{1} << shift_;
      }
    }
    // Full counting is faster while its counts fit in a typical L2 cache (1 MiB).
    windowed_ = how == detail::RankCounting::windowed ||
                (how == detail::RankCounting::automatic && n > (std::size_t{1} << 18) && covered <= n / 8);
    if (windowed_) {
      bucket_counts_.resize(buckets);
      fine_counts_.resize(covered);
    }
  }

  // Draws the resample of `rng` and stores sorted[r] of each wanted order statistic in `out`.
  void resample(const Rng& rng, std::span<std::int64_t> out) {
    // The caller checked n < 2^32.
    if (!windowed_ || !resample_windowed(rng, out)) resample_full(rng, out);
  }

  std::size_t fallbacks() const { return fallbacks_; }

 private:
  static constexpr std::size_t kNoFine = ~std::size_t{0};

  void resample_full(const Rng& rng, std::span<std::int64_t> out) {
    const std::size_t n = sorted_.size();
    IndexStream draw(rng, static_cast<std::uint32_t>(n));
    if (full_counts_.size() != n) full_counts_.resize(n);
    std::fill(full_counts_.begin(), full_counts_.end(), 0u);
    for (std::size_t i = 0; i < n; ++i) ++full_counts_[draw.next()];
    std::size_t r = 0;
    std::uint64_t below_r = 0;  // resample elements with rank < r
    for (std::size_t s = 0; s < wanted_.size(); ++s) {
      while (below_r + full_counts_[r] <= wanted_[s]) below_r += full_counts_[r++];
      out[s] = sorted_[r];
    }
  }

  bool resample_windowed(const Rng& rng, std::span<std::int64_t> out) {
    std::fill(bucket_counts_.begin(), bucket_counts_.end(), 0u);
    std::fill(fine_counts_.begin(), fine_counts_.end(), 0u);
    const std::size_t n = sorted_.size();
    const std::size_t mask = (std::size_t{1} << shift_) - 1;
    IndexStream draw(rng, static_cast<std::uint32_t>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t r = draw.next();
      const std::size_t bucket = r >> shift_;
      ++bucket_counts_[bucket];
      const std::size_t offset = fine_offset_[bucket];
      if (offset != kNoFine) ++fine_counts_[offset + (r & mask)];
    }
    std::size_t bucket = 0;
    std::uint64_t below = 0;  // resample elements in buckets before `bucket`
    for (std::size_t s = 0; s < wanted_.size(); ++s) {
      const std::size_t j = wanted_[s];
      while (below + bucket_counts_[bucket] <= j) below += bucket_counts_[bucket++];
      const std::size_t offset = fine_offset_[bucket];
      if (offset == kNoFine) {
        ++fallbacks_;
        return false;
      }
      std::uint64_t below_r = below;
      std::size_t k = 0;
      while (below_r + fine_counts_[offset + k] <= j) below_r += fine_counts_[offset + k++];
      out[s] = sorted_[(bucket << shift_) + k];
    }
    return true;
  }

  std::span<const std::int64_t> sorted_;
  std::span<const std::size_t> wanted_;  // ascending order-statistic ranks within a resample
  bool windowed_ = false;
  int shift_ = 6;                         // buckets of 2^shift_ ranks
  std::vector<std::size_t> fine_offset_;  // per bucket: start of its per-rank counts, or kNoFine
  std::vector<std::uint32_t> bucket_counts_;
  std::vector<std::uint32_t> fine_counts_;
  std::vector<std::uint32_t> full_counts_;
  std::size_t fallbacks_ = 0;
};

}  // namespace

namespace detail {

std::size_t bootstrap_threads(std::size_t n, std::size_t resamples) {
  // Below ~16 M draws (tens of ms) a thread's start costs more than it saves.
  if (n * resamples < (std::size_t{1} << 24)) return 1;
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  return std::min<std::size_t>(cores, kMaxBootstrapThreads);
}

BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed, RankCounting how, std::size_t half_width,
                                       std::size_t* fallbacks, std::size_t threads) {
  const std::size_t n = sorted_ns.size();
  if (n == 0) throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: empty sample");
  // A rank's count is at most n; 32-bit counts halve the memory the draws scatter over.
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("bootstrap_quantiles: {} samples is too many", n));
  }
  if (!std::is_sorted(sorted_ns.begin(), sorted_ns.end())) {
    throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: the sample is not sorted");
  }

  // The order statistics (0-based ranks within a resample) the quantiles interpolate between.
  std::vector<QuantilePosition> positions;
  std::vector<std::size_t> ranks;
  for (const double p : probabilities) {
    const QuantilePosition at = quantile_position(n, p);
    positions.push_back(at);
    ranks.push_back(at.lower);
    if (at.fraction != 0.0) ranks.push_back(at.lower + 1);
  }
  std::sort(ranks.begin(), ranks.end());
  ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
  const auto slot = [&](std::size_t rank) {
    return static_cast<std::size_t>(std::lower_bound(ranks.begin(), ranks.end(), rank) - ranks.begin());
  };

  BootstrapQuantiles out;
  out.probabilities.assign(probabilities.begin(), probabilities.end());
  out.resamples = resamples;
  out.values.resize(resamples * probabilities.size());

  // Resamples b = first .. last-1 into out.values; returns how many fell back to full counting.
  // Each resample draws from its own stream (seed, b), so how they are shared among threads
  // changes nothing in the result.
  const auto run = [&](std::size_t first, std::size_t last) {
    RankCounter counter(sorted_ns, ranks, how, half_width);
    std::vector<std::int64_t> order_stats(ranks.size());
    for (std::size_t b = first; b < last; ++b) {
      counter.resample(Rng::stream(seed, b), order_stats);
      for (std::size_t k = 0; k < positions.size(); ++k) {
        const QuantilePosition& at = positions[k];
        const std::int64_t a = order_stats[slot(at.lower)];
        out.values[b * positions.size() + k] =
            at.fraction == 0.0 ? static_cast<double>(a)
                               : interpolate(a, order_stats[slot(at.lower + 1)], at.fraction);
      }
    }
    return counter.fallbacks();
  };

  if (threads == 0) threads = bootstrap_threads(n, resamples);
  threads = std::clamp<std::size_t>(threads, 1, std::max<std::size_t>(resamples, 1));
  // Share t is resamples [B t / threads, B (t + 1) / threads).
  std::vector<std::size_t> fallback_counts(threads, 0);
  std::vector<std::exception_ptr> errors(threads);
  const auto run_share = [&](std::size_t t) {
    try {
      fallback_counts[t] = run(resamples * t / threads, resamples * (t + 1) / threads);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  {
    std::vector<std::jthread> workers;
    std::size_t started = 1;  // share 0 is this thread's
    try {
      for (; started < threads; ++started) workers.emplace_back(run_share, started);
    } catch (const std::system_error&) {
      // No more threads to be had (a resource limit): this thread takes the shares left.
    }
    run_share(0);
    for (std::size_t t = started; t < threads; ++t) run_share(t);
  }  // the workers join here
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  if (fallbacks != nullptr)
    *fallbacks = std::accumulate(fallback_counts.begin(), fallback_counts.end(), std::size_t{0});
  return out;
}

}  // namespace detail

BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed) {
  return detail::bootstrap_quantiles(sorted_ns, probabilities, resamples, seed,
                                     detail::RankCounting::automatic);
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
