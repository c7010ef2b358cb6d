// What a store recorded on a scenario's two boards besides their events, loaded once: the clock
// samples (as time series to draw, and as the tracks the per-sample uncertainty of uncertainty.hpp
// is computed from) and the losses. The report draws these; it does not read the store itself.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/stats/summary.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

struct ScenarioResult;
struct ScenarioInput;

// One board's clock samples over a scenario as recorded (every source, steps included), in time
// order, on the scenario's clock: what a figure of the board's clock state draws.
struct ClockSeries {
  std::string node;
  std::string source;                      // of the first sample, e.g. "chrony", "sim"
  std::vector<std::int64_t> t_ns;          // when each sample was taken (ns, the scenario's clock)
  std::vector<std::int64_t> offset_ns;     // estimated offset from the reference (ns)
  std::vector<std::int64_t> max_error_ns;  // maximum error bound (ns)
};

// Recorded losses of one board and kind (gaps in the kernel's sequence numbers, overflows, ...).
struct LossCount {
  std::string node, kind;
  std::size_t records = 0;   // loss records
  std::uint64_t events = 0;  // events known missing
};

// What was recorded on a scenario's two boards besides their events: read from a store, or the
// clock records of events files (then without losses).
struct BoardRecord {
  std::map<std::string, std::vector<store::ClockSample>> samples;  // by node, in session (file) order
  std::vector<LossCount> losses;                                   // by node, then kind
  // By node: the steps its kernel log cannot show (kernel_log_steps.hpp), when there is a note to give.
  std::map<std::string, LogClockLimits> log_limits;
  // By node: the stamps of its log lines on no known clock (store/clock_step.hpp), whose events are
  // left out before pairing; kept apart from `samples`, which describe the clock.
  std::map<std::string, std::vector<store::UnknownClock>> unknown_clock;
  std::span<const store::ClockSample> of(const std::string& node) const;  // empty if none
  // Adds a stored or carried clock sample of `node`: an "unknown_clock" record to unknown_clock, any
  // other to samples.
  void add(const std::string& node, store::ClockSample sample);
};
// The clock samples and losses of the scenario's sessions on its cause and effect nodes (one pass
// over the store).
BoardRecord read_board_record(const store::Store& store, const ScenarioInput& input);

// From `record`, fills result.clocks (one series per node, by node name), result.losses, result.uncertainty
// (attach_uncertainty with `options`, from the same samples) and the per-board error budget
// result.cause_clock_ms / effect_clock_ms.
void attach_board_record(ScenarioResult& result, const BoardRecord& record, const UncertaintyOptions& options,
                         const stats::SummaryOptions& summary_options);

// Reads the clock samples and losses of the scenario's sessions on its cause and effect nodes (one
// pass over the store) and fills result.clocks (one series per node, by node name), result.losses
// (by node, then kind), result.uncertainty (attach_uncertainty with `options`, from the same
// samples) and the per-board error budget result.cause_clock_ms / effect_clock_ms.
void attach_board_record(ScenarioResult& result, const store::Store& store, const UncertaintyOptions& options,
                         const stats::SummaryOptions& summary_options);

}  // namespace m2mlat::analysis
