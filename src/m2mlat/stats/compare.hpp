// Comparison of two latency samples: is the subject's latency different from the baseline's, in
// location and in spread, by more than chance and by more than the measurement's own uncertainty?
//
// "5G vs WiFi": subject = 5G, baseline = WiFi. Differences are subject - baseline, ratios
// subject / baseline (an IQR ratio of 0.53 is "47 % narrower").
//
// - median difference, with a bootstrap percentile CI: each sample is resampled on its own
//   (bootstrap_quantiles, B resamples), resample b of one paired with resample b of the other;
// - IQR ratio and SD ratio, with bootstrap percentile CIs the same way;
// - Mann-Whitney U (location, two-sided p) and Brown-Forsythe (spread, p);
// - per threshold, the difference of the shares above it, with Newcombe's hybrid score interval
//   (method 10 of Newcombe 1998, from two Wilson intervals);
// - whether the median difference and the IQR difference are smaller than a given measurement
//   uncertainty (a bound on one latency's error from both boards' clocks, docs/report.md).
//
// A sample given in time order with its units (a scenario's pairs and manoeuvres) is resampled as
// bootstrap.hpp's plan_resampling says: whole manoeuvres, in blocks where they are correlated; the
// resamples' quartiles and SD then come from unit_replicates.
//
// Reproducibility: the two samples' resamples use different seeds derived from options.seed with
// splitmix64 (the first two outputs for the quantiles, the next two for the SDs), so that two
// samples of equal size never draw the same ranks; same seed, same intervals on every platform.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"
#include "m2mlat/stats/bootstrap.hpp"
#include "m2mlat/stats/brown_forsythe.hpp"
#include "m2mlat/stats/mann_whitney.hpp"

namespace m2mlat::stats {

struct CompareOptions {
  std::size_t resamples = 2000;  // B; 0 = no bootstrap intervals (they are then NaN)
  std::uint64_t seed = 1;
  double level = 0.95;  // of every interval, in (0, 1)
  double alpha = 0.05;  // significance level of the two tests
  std::vector<core::Duration> thresholds;
  // A bound on one latency sample's error (ms), e.g. the median of the per-pair bounds from the
  // boards' clock state; unset = unknown (no note is made).
  std::optional<double> uncertainty_ms;
};

struct ShareDifference {
  core::Duration threshold{0};
  std::size_t count_subject = 0, count_baseline = 0;  // samples strictly above the threshold
  double share_subject = 0.0, share_baseline = 0.0;   // fractions in [0, 1]
  double difference = 0.0;                            // share_subject - share_baseline
  Interval ci;                                        // Newcombe hybrid score interval at `level`
};

struct Comparison {
  std::size_t n_subject = 0, n_baseline = 0;
  double median_subject_ms = 0.0, median_baseline_ms = 0.0;
  double iqr_subject_ms = 0.0, iqr_baseline_ms = 0.0;
  double sd_subject_ms = 0.0, sd_baseline_ms = 0.0;

  double median_difference_ms = 0.0;  // subject - baseline
  Interval median_difference_ci_ms;
  double iqr_ratio = 0.0;  // subject / baseline; NaN if the baseline's IQR is 0
  Interval iqr_ratio_ci;
  double sd_ratio = 0.0;  // subject / baseline
  Interval sd_ratio_ci;

  MannWhitney mann_whitney;      // location: subject = sample a
  BrownForsythe brown_forsythe;  // spread
  std::vector<ShareDifference> shares;

  std::optional<double> uncertainty_ms;
  // What each side's intervals resampled (samples one by one for a sample not given in time order).
  Resampling subject_resampling, baseline_resampling;
  bool median_difference_below_uncertainty = false;  // |median difference| < uncertainty
  bool iqr_difference_below_uncertainty = false;     // |IQR_subject - IQR_baseline| < uncertainty

  // What the options were, so the result can be reproduced.
  std::size_t resamples = 0;
  std::uint64_t seed = 0;
  double level = 0.0;
  double alpha = 0.0;

  bool location_significant() const { return mann_whitney.p < alpha; }
  bool spread_significant() const { return brown_forsythe.p < alpha; }
};

// One side of a comparison: its latencies (ns) and, when they are in time order, where its units begin
// (empty: each its own).
struct CompareSample {
  std::span<const std::int64_t> ns;
  bool in_time_order = false;
  std::span<const std::size_t> unit_starts;
};

// Both samples in ns, each with at least 2 values (else core::Error(data) naming which). Throws
// core::Error(usage) for a bad level or alpha.
Comparison compare(const CompareSample& subject, const CompareSample& baseline, const CompareOptions& options = {});
// The same for samples in any order, each value resampled on its own.
Comparison compare(std::span<const std::int64_t> subject_ns, std::span<const std::int64_t> baseline_ns,
                   const CompareOptions& options = {});

// Newcombe's hybrid score interval for p1 - p2 from counts k1 of n1 and k2 of n2 (n1, n2 > 0), with
// z the two-sided normal quantile of `level`. Exposed for tests.
Interval newcombe_interval(std::size_t k1, std::size_t n1, std::size_t k2, std::size_t n2, double level);

// The bootstrap distribution of the sample standard deviation (ms) of a sorted sample, B values.
std::vector<double> bootstrap_sd_ms(std::span<const std::int64_t> sorted_ns, std::size_t resamples,
                                    std::uint64_t seed);

}  // namespace m2mlat::stats
