// What the flagged pairs would do to a scenario's statistics: its median and IQR with them and without
// them, so that a reader sees whether leaving them out (or taking them in, with --include-ambiguous)
// moves the result (docs/statistics.md, "What is left out").
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "m2mlat/stats/bootstrap.hpp"

namespace m2mlat::analysis {

struct FlaggedEffect {
  std::size_t flagged = 0;       // pairs with a pairing flag (pairing::kPairUncertain)
  bool included = false;         // the statistics hold them (--include-ambiguous)
  std::size_t n_without = 0, n_with = 0;
  double median_without_ms = 0, median_with_ms = 0;
  double iqr_without_ms = 0, iqr_with_ms = 0;
  // Half the statistics' 95 % CI width (ms) of the median and of the IQR; unset without a bootstrap.
  std::optional<double> half_median_ci_ms, half_iqr_ci_ms;
  double median_shift_ms() const { return median_with_ms - median_without_ms; }
  double iqr_shift_ms() const { return iqr_with_ms - iqr_without_ms; }
  // The flagged pairs move the median (or the IQR) by more than half its confidence interval.
  bool median_moves() const { return half_median_ci_ms && std::abs(median_shift_ms()) > *half_median_ci_ms; }
  bool iqr_moves() const { return half_iqr_ci_ms && std::abs(iqr_shift_ms()) > *half_iqr_ci_ms; }
};

// The effect from the statistics' sorted sample and the flagged pairs' sorted latencies (ns), nullopt
// when no pair is flagged. `included`: the sample holds the flagged pairs; `ci`: its bootstrap, if any.
std::optional<FlaggedEffect> flagged_effect(std::span<const std::int64_t> statistics_sorted,
                                            std::span<const std::int64_t> flagged_sorted, bool included,
                                            const std::optional<stats::MedianIqrCi>& ci);

// The k-th smallest (0-based) value of the multiset `sorted` plus `other` (add) or minus `other` (other
// a sub-multiset of sorted: the values left when it is taken out); both ascending. k below the size.
std::int64_t kth_value(std::span<const std::int64_t> sorted, std::span<const std::int64_t> other, bool add,
                       std::size_t k);

}  // namespace m2mlat::analysis
