// What a report shows, gathered once and written by every writer (text, Markdown, CSV, JSON, HTML,
// pgfplots): the analysed scenarios with their group, each pair's uncertainty from both boards'
// clock state, the clock samples and losses of the boards, the comparisons asked for, and the exact
// command and versions that produced it. Everything is recomputed from raw events by the command.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/stats/compare.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::report {

// One board's clock state over a scenario, from the store's clock samples (time order).
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

struct ScenarioReport {
  analysis::ScenarioResult result;
  std::string group;  // empty: no group
  // One entry per result.match.pairs: cause board's max error at the cause time + effect board's at
  // the effect time (ns); nullopt when a board has no clock sample.
  std::vector<std::optional<std::int64_t>> uncertainty_ns;
  std::vector<ClockSeries> clocks;
  std::vector<LossCount> losses;

  // Median of the known per-pair bounds over the pairs in the statistics (ms); unset if none known.
  std::optional<double> median_uncertainty_ms() const;
  // The largest of them (ms).
  std::optional<double> max_uncertainty_ms() const;
  // The medians of the cause board's and the effect board's bounds alone (ms): the error budget.
  std::optional<double> cause_clock_ms, effect_clock_ms;
};

struct ComparisonReport {
  std::string subject, baseline;  // scenario names: "subject vs baseline"
  stats::Comparison comparison;
};

struct Report {
  std::vector<ScenarioReport> scenarios;
  std::vector<std::string> groups;  // in order of first appearance; empty: no grouping
  std::vector<ComparisonReport> comparisons;
  std::string command;                                        // the exact command line
  std::vector<std::pair<std::string, std::string>> versions;  // ("m2mlat", "0.1.0"), ...
  std::optional<double> assumed_uncertainty_ms;  // given by the user for scenarios without clock data
  double alpha = 0.05;

  const ScenarioReport* find(const std::string& scenario) const;
};

// The clock series, losses and per-pair uncertainty of a scenario analysed from `store`: the
// sessions of the scenario on the cause and effect nodes.
void attach_store_data(ScenarioReport& scenario, const store::Store& store);

// Per-pair uncertainty from two boards' clock series (the latest sample at or before each time, or
// the first sample when the time is earlier than all). Exposed for tests.
std::optional<std::int64_t> clock_bound_at(const ClockSeries& series, std::int64_t t_ns);

// Groups: `explicit_groups` (name -> scenarios) if given; otherwise, when `by_prefix`, the part of
// each scenario name before its first '_' or '-' (used only if it gives at least two groups, or one
// group of several scenarios); otherwise none. Fills ScenarioReport::group and Report::groups.
void assign_groups(Report& report,
                   const std::vector<std::pair<std::string, std::vector<std::string>>>& explicit_groups,
                   bool by_prefix);

// The default comparisons: within each group (or among all scenarios without groups), every later
// scenario against every earlier one ("static_5g vs static_wifi").
std::vector<std::pair<std::string, std::string>> default_comparisons(const Report& report);

// Runs one comparison of two scenarios already in the report (core::Error(usage) for an unknown
// name). The uncertainty used is the larger of the two scenarios' median per-pair bounds, or the
// report's assumed uncertainty when neither has clock data.
ComparisonReport compare_scenarios(const Report& report, const std::string& subject,
                                   const std::string& baseline, stats::CompareOptions options);

}  // namespace m2mlat::report
