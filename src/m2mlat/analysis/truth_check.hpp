// How a measurement compares with the simulator's ground truth: which pairs the matcher found are
// the true ones, which it missed, which are wrong, and how far the measured latencies are from the
// true latencies (the clocks' disagreement plus the interrupt latency).
//
// The acceptance criterion (docs/simulator.md, "The truth check"): no wrong pair reaches the
// statistics unflagged, and at least 95 % of the true pairs are found (flagged or not). A flagged
// pair is one with any pairing::PairFlag bit: the user is told why it may be wrong.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/sim/truth.hpp"

namespace m2mlat::analysis {

// The least share of the true pairs the matcher must find (reported, flagged or not), percent.
inline constexpr std::int64_t kMinFoundPercent = 95;

struct TruthCheck {
  std::int64_t true_pairs = 0;        // passes detected on both sides
  std::int64_t found = 0;             // pairs the matcher produced
  std::int64_t correct = 0;           // found and true
  std::int64_t wrong = 0;             // found but not true
  std::int64_t wrong_clear = 0;       // ... among the pairs not flagged ambiguous
  std::int64_t wrong_flagged = 0;     // ... among the pairs with a flag (any PairFlag bit)
  std::int64_t wrong_unflagged = 0;   // ... among the pairs with no flag: silent errors
  std::int64_t ambiguous = 0;         // pairs flagged ambiguous
  std::int64_t missed = 0;            // true but not found
  double true_median_ms = 0;          // median of the true latencies of the true pairs
  std::int64_t max_abs_error_ns = 0;  // max |measured - true latency| over the correct pairs
  double mean_error_ns = 0;           // mean (measured - true latency) over the correct pairs

  // The per-sample uncertainty (analysis/uncertainty.hpp) against the truth, over the correct pairs
  // whose uncertainty is bounded (wrong pairs are a pairing question, not a clock one): how often the
  // true latency lies within +-u (k = 1: about 68 % when honest), +-U95 (k = 2: about 95 %) and
  // +-max_error (always), and how wide U95 is against the real errors. All zero (ratios NaN) when the
  // result has no uncertainty (no clock samples).
  std::int64_t with_uncertainty = 0;  // correct pairs with a bounded uncertainty
  std::int64_t within_u = 0;          // |measured - true latency| <= u
  std::int64_t within_U95 = 0;        // ... <= U95
  std::int64_t within_max = 0;        // ... <= max_error
  double median_U95_ns = 0;           // median U95 over those pairs
  double median_abs_error_ns = 0;     // median |measured - true latency| over the same pairs

  bool exact() const { return wrong == 0 && missed == 0; }
  // correct / true pairs, in percent (100 when there is no true pair).
  double found_percent() const;
  // The acceptance criterion: no unflagged wrong pair, and >= kMinFoundPercent % of the true pairs found.
  bool passes() const;

  double coverage_u() const { return share(within_u); }
  double coverage_U95() const { return share(within_U95); }
  double coverage_max() const { return share(within_max); }
  // median U95 / median |error|: 2.97 for a normal error whose sd u is exact; wider is pessimistic.
  double width_ratio() const;

 private:
  double share(std::int64_t k) const;
};

// One correct pair with a bounded uncertainty: its |measured - true latency| and its uncertainty.
struct CoveragePoint {
  std::int64_t abs_error_ns = 0;
  SampleUncertainty uncertainty;
};
// The points the coverage figures of TruthCheck are computed from, in pair order (same conditions as
// check_against_truth); empty when the result has no uncertainty.
std::vector<CoveragePoint> coverage_points(const ScenarioResult& result,
                                           const std::vector<sim::TruePair>& pairs);

// `result` must come from the run whose truth is `pairs`, with the events in the simulator's order
// (pair indices = the simulator's event indices, as when read back from a store in time order).
// The true pairs with their indices moved from the nodes' event lists to the loaded columns, where
// a column's position is not the event's index: a line recorded with both edges (the column holds
// one kind) or edges dropped before pairing (Selection::min_pulse). `cause_stamps[k]` is the cause
// node's k-th event's timestamp (ns), INT64_MIN for an event of the kind not paired; an event is
// found in its column by its timestamp. A pair whose edge is not in its column (dropped as
// interference) gets index -1: it can only be missed.
std::vector<sim::TruePair> in_columns(std::vector<sim::TruePair> pairs,
                                      std::span<const std::int64_t> cause_stamps,
                                      std::span<const std::int64_t> effect_stamps,
                                      const ScenarioInput& input);

TruthCheck check_against_truth(const ScenarioResult& result,
                               const std::vector<sim::TruePair>& pairs);

}  // namespace m2mlat::analysis
