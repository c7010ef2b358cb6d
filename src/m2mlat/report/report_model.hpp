// What a report shows, gathered once and written by every writer (text, Markdown, CSV, JSON, HTML,
// pgfplots): the analysed scenarios with their group, each pair's uncertainty, the clock samples and
// losses of the boards, the comparisons asked for, and the exact command and versions that produced
// it. Every number comes from the analysis pipeline (analysis/pipeline.hpp): the report computes no
// clock bound of its own and reads no store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/stats/compare.hpp"

namespace m2mlat::report {

struct ScenarioReport {
  analysis::ScenarioResult result;  // with the boards' clock series, losses and error budget
  std::string group;                // empty: no group
  // Per result.match.pairs entry, from the analysis (analysis/uncertainty.hpp) where bounded (ns;
  // nullopt when unknown or unbounded): the expanded uncertainty U95 (k = 2), drawn as error bars and
  // used by the comparisons, and the worst-case bound max_error beside it.
  std::vector<std::optional<std::int64_t>> uncertainty_ns;
  std::vector<std::optional<std::int64_t>> max_error_ns;

  // Median of the known per-pair U95 over the pairs in the statistics (ms); unset if none known.
  std::optional<double> median_uncertainty_ms() const;
  // The largest of them (ms).
  std::optional<double> max_uncertainty_ms() const;
  // Median of the known per-pair bounds over the same pairs (ms).
  std::optional<double> median_bound_ms() const;

 private:
  // The known values of `values` (one per pair) over the pairs in the statistics.
  std::vector<std::int64_t> known_in_statistics(const std::vector<std::optional<std::int64_t>>& values) const;
};

// A scenario of the report from the pipeline's result: uncertainty_ns and max_error_ns from
// result.uncertainty.
ScenarioReport scenario_report(analysis::ScenarioResult result);

struct ComparisonReport {
  std::string subject, baseline;  // scenario names: "subject vs baseline"
  stats::Comparison comparison;
};

struct Report {
  std::vector<ScenarioReport> scenarios;
  std::vector<std::string> groups;  // in order of first appearance; empty: no grouping
  std::vector<ComparisonReport> comparisons;
  // The full-loop rig's files (analysis/full_loop.hpp): M2M, G2G, E2E and motion durations per file.
  std::vector<analysis::FullLoopResult> full_loops;
  std::string command;                                        // the exact command line
  std::vector<std::pair<std::string, std::string>> versions;  // ("m2mlat", "0.1.0"), ...
  std::optional<double> assumed_uncertainty_ms;  // given by the user for scenarios without clock data
  double alpha = 0.05;

  const ScenarioReport* find(const std::string& scenario) const;
  const analysis::FullLoopResult* find_full_loop(const std::string& scenario) const;
  // The palette index of each of `scenarios` (scenario_colours.hpp), and of one scenario by name.
  std::vector<std::size_t> colours() const;
  std::size_t colour(const std::string& scenario) const;
};

// Groups: `explicit_groups` (name -> scenarios) if given; otherwise, when `by_prefix`, the part of
// each scenario name before its first '_' or '-' (used only if it gives at least two groups, or one
// group of several scenarios); otherwise none. Fills ScenarioReport::group and Report::groups.
void assign_groups(Report& report,
                   const std::vector<std::pair<std::string, std::vector<std::string>>>& explicit_groups,
                   bool by_prefix);

// The default comparisons: within each group (or among all scenarios without groups), every later
// scenario against every earlier one ("static_5g vs static_wifi": the first scenario given is the
// baseline). With a `baseline`, every other scenario of its group (of all, without groups) against it,
// and the other groups as before; a baseline not in the report is core::Error(usage).
std::vector<std::pair<std::string, std::string>> default_comparisons(const Report& report,
                                                                     const std::string& baseline = {});

// Runs one comparison of two scenarios already in the report (core::Error(usage) for an unknown
// name). The uncertainty used is the larger of the two scenarios' median per-pair bounds, or the
// report's assumed uncertainty when neither has clock data.
ComparisonReport compare_scenarios(const Report& report, const std::string& subject,
                                   const std::string& baseline, stats::CompareOptions options);

// Two full-loop files compared (by their scenario names): one comparison per quantity of M2M, G2G
// and E2E that both files have with at least 2 values each, named "<file> <quantity>" ("b E2E" vs
// "a E2E"); the camera file's G2G is compared with a result CSV's G2G. The uncertainty is the
// report's assumed one (the files carry no clock data). core::Error(usage) for an unknown name.
std::vector<ComparisonReport> compare_full_loops(const Report& report, const std::string& subject,
                                                 const std::string& baseline, stats::CompareOptions options);
// The default: every later full-loop file against every earlier one.
std::vector<std::pair<std::string, std::string>> default_full_loop_comparisons(const Report& report);

}  // namespace m2mlat::report
