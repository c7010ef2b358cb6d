// Terminal views of analysed scenarios: one row per scenario, and the full detail of one.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::report {

// The cells of one scenario's summary row (ms, 1 decimal): n, median, IQR, mean, sd, min, max, P95,
// then the share above each threshold. Shared by the terminal table and the HTML report.
std::vector<std::string> summary_cells(const stats::Summary& summary);
// One row per scenario: pairs, unmatched, median, IQR, mean, sd, min, max, P95, shares above.
std::string scenario_table(std::span<const analysis::ScenarioResult> results);
// Every statistic of one scenario, with the identity of the min/max samples and the CIs.
std::string scenario_detail(const analysis::ScenarioResult& result);
// Counts of pairs and of unmatched events by side and reason, one row per scenario.
std::string pairing_table(std::span<const analysis::ScenarioResult> results);
// The per-sample uncertainty of the scenarios whose boards had clock samples (median and P95 of
// u and U95, median/P95/worst max_err, shares flagged); empty text when none had.
std::string uncertainty_table(std::span<const analysis::ScenarioResult> results);
// The median and IQR of each scenario with flagged pairs, with them and without them, and whether they
// move either by more than half its CI; empty text when no scenario has flagged pairs.
std::string flagged_effect_table(std::span<const analysis::ScenarioResult> results);
// The same table's header, and one scenario's row (ms, 1 decimal; empty without flagged pairs), for the
// Markdown and HTML reports.
std::vector<std::string> flagged_effect_header();
std::vector<std::string> flagged_effect_row(const analysis::ScenarioResult& result);
// Per board whose kernel log showed its clock slewing faster than the steps' bound: "<node>: the
// kernel log's realtime clock slews faster than 500 ppm at K places: ..." (kernel_log_steps.hpp).
std::vector<std::string> clock_limit_notes(const analysis::ScenarioResult& r);
// The boards' clock steps and what they did to the pairs (corrected by a known size, or flagged and
// left out of the statistics), one row per scenario with steps or fast slewing, the latter's notes
// below; empty text when none had any.
std::string clock_step_table(std::span<const analysis::ScenarioResult> results);

}  // namespace m2mlat::report
