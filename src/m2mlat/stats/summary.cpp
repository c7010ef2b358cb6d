// Computing the summary: one pass for extremes and the exact sum, one sort, one pass for the
// standard deviation, then quantiles, threshold shares and the bootstrap from the sorted sample.
#include "m2mlat/stats/summary.hpp"

#include <algorithm>

#include "m2mlat/stats/moments.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/radix_sort.hpp"

namespace m2mlat::stats {

namespace {

constexpr double kNsPerMs = 1e6;

}  // namespace

Summary summarize(std::span<const std::int64_t> latencies_ns, std::span<const std::int64_t> ids,
                  const SummaryOptions& options, std::span<const std::size_t> unit_starts) {
  std::vector<std::int64_t> copy(latencies_ns.begin(), latencies_ns.end());
  return summarize_in_place(copy, ids, options, unit_starts);
}

Summary summarize_in_place(std::span<std::int64_t> latencies_ns, std::span<const std::int64_t> ids,
                           const SummaryOptions& options, std::span<const std::size_t> unit_starts) {
  // Validate every option before doing any work, so that a bad one fails fast even on 1e7 samples.
  for (const double percent : options.extra_percentiles) check_percentile(percent);
  if (options.bootstrap) check_confidence_level(options.bootstrap->level);

  Summary s;
  s.n = latencies_ns.size();
  if (const std::optional<Extremes> e = find_extremes(latencies_ns, ids)) {
    s.min = e->min;
    s.max = e->max;
  }

  // How to resample is read from the time order, which the sort takes away; a plan that is not the
  // plain bootstrap of independent samples resamples before the sort.
  std::optional<Resampling> plan;
  if (options.bootstrap && s.n > 0) {
    plan = plan_resampling(latencies_ns, unit_starts);
    if (!plan->sample_by_sample()) s.bootstrap = resample_median_iqr(latencies_ns, unit_starts, *plan, *options.bootstrap);
  }
  sort_ns(latencies_ns);
  const std::span<const std::int64_t> view(latencies_ns);

  s.thresholds = threshold_shares(view, options.thresholds);
  for (const double percent : options.extra_percentiles) {
    s.extra_percentiles.push_back({percent, quantile(view, percent / 100.0) / kNsPerMs});
  }
  if (s.n == 0) return s;

  // The sorted sample serves the moments too: the order of summation does not matter to an exact
  // sum, and the sd is computed over the sorted order whichever function was called.
  const Mean mean = exact_mean(view);
  s.mean_ms = mean.mean / kNsPerMs;
  s.sd_ms = sample_sd(view, mean) / kNsPerMs;

  const auto q = [&](double p) { return quantile(view, p) / kNsPerMs; };
  s.p5_ms = q(0.05);
  s.q1_ms = q(0.25);
  s.median_ms = q(0.5);
  s.q3_ms = q(0.75);
  s.p90_ms = q(0.90);
  s.p95_ms = q(0.95);
  s.p99_ms = q(0.99);
  s.iqr_ms = (quantile(view, 0.75) - quantile(view, 0.25)) / kNsPerMs;

  if (plan && plan->sample_by_sample()) {
    s.bootstrap = bootstrap_median_iqr(view, *options.bootstrap);
    if (s.bootstrap) s.bootstrap->resampling = *plan;
  }
  return s;
}

}  // namespace m2mlat::stats
