// The descriptive summary of one latency sample: the numbers every report prints.
//
// Input is latencies in int64 ns (effect - cause, already subtracted in integers upstream) and
// optionally one id per sample (pair index or store sequence number), so that the minimum and
// maximum can name their sample. Everything floating point is in milliseconds and says so in its
// name (median_ms); exact values stay in ns (Extreme::ns, ThresholdShare::threshold).
//
// Definitions (docs/statistics.md): mean from an exact integer sum (within 1 ulp); sd with divisor n - 1;
// quantiles type 7 (numpy's default) on the sorted sample; IQR = q3 - q1; "above a threshold"
// means strictly greater. Undefined values are NaN: every statistic for n = 0, sd for n = 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"
#include "m2mlat/stats/bootstrap.hpp"
#include "m2mlat/stats/extremes.hpp"
#include "m2mlat/stats/threshold.hpp"

namespace m2mlat::stats {

struct SummaryOptions {
  std::vector<double> extra_percentiles;                          // in percent, [0, 100], e.g. {99.9}
  std::vector<core::Duration> thresholds = default_thresholds();  // {170 ms, 300 ms, 400 ms, 1 s}
  std::optional<BootstrapOptions> bootstrap;                      // unset: no confidence intervals
};

struct PercentileValue {
  double percent = 0.0;  // [0, 100]
  double value_ms = 0.0;
};

struct Summary {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

  std::size_t n = 0;
  std::optional<Extreme> min;  // unset for n = 0; ties: the first sample in input order
  std::optional<Extreme> max;
  double mean_ms = kNaN;
  double sd_ms = kNaN;  // sample standard deviation (n - 1); NaN for n < 2
  double p5_ms = kNaN;
  double q1_ms = kNaN;  // P25
  double median_ms = kNaN;
  double q3_ms = kNaN;  // P75
  double p90_ms = kNaN;
  double p95_ms = kNaN;
  double p99_ms = kNaN;
  double iqr_ms = kNaN;                            // q3 - q1
  std::vector<PercentileValue> extra_percentiles;  // in the order of SummaryOptions::extra_percentiles
  std::vector<ThresholdShare> thresholds;          // in the order of SummaryOptions::thresholds
  std::optional<MedianIqrCi> bootstrap;            // when requested and n > 0
};

// `latencies_ns` in time order; `ids` is empty or one per latency (else core::Error(internal)); a bad
// percentile or confidence level throws core::Error(usage). `unit_starts` groups the latencies into the
// units the bootstrap resamples together (bootstrap.hpp: plan_resampling; empty: each on its own).
// Sorts one copy of the sample; the input is not changed.
Summary summarize(std::span<const std::int64_t> latencies_ns, std::span<const std::int64_t> ids = {},
                  const SummaryOptions& options = {}, std::span<const std::size_t> unit_starts = {});

// The same without the copy, for a sample the caller builds for the purpose: sorts `latencies_ns` in
// place (8 bytes a sample fewer at the peak, 74 MB for 9.3 M latencies). The extremes are found before
// the sort, so they, their ids and their ties are those of summarize().
Summary summarize_in_place(std::span<std::int64_t> latencies_ns, std::span<const std::int64_t> ids = {},
                           const SummaryOptions& options = {}, std::span<const std::size_t> unit_starts = {});

}  // namespace m2mlat::stats
