// The stage breakdown of each scenario (analysis/breakdown.hpp) in every output: a terminal table,
// the `breakdown` member of m2mlat-stats/1, per-event rows (m2mlat-breakdown/1 CSV), a stacked bar
// per scenario as SVG for the HTML report and as a pgfplots figure. Draws; computes nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::report {

inline constexpr const char* kBreakdownFormat = "m2mlat-breakdown/1";

// The scenarios that have a breakdown, in order: what the functions below take.
using BreakdownResults = std::vector<const analysis::ScenarioResult*>;
BreakdownResults with_breakdown(std::span<const analysis::ScenarioResult> results);

// Per scenario with a breakdown: its stages (median, quartiles, IQR, mean, share, ms) and its
// incomplete chains by stage and reason. Empty text when no scenario has a breakdown.
std::string breakdown_table(const BreakdownResults& results);
// The `breakdown` member of a scenario in m2mlat-stats/1 (docs/formats.md).
nlohmann::json breakdown_json(const analysis::Breakdown& breakdown);
// One row per event of every scenario with a breakdown (docs/formats.md, m2mlat-breakdown/1).
std::string breakdown_csv(const BreakdownResults& results);
// Stacked bars of the stages' means (one bar per scenario, adding up to its mean M2M), data-chart
// "breakdown"; empty when no scenario has a breakdown.
std::string breakdown_svg(const BreakdownResults& results);
// The same as a pgfplots figure: (file name, text) of breakdown.tex and breakdown.dat; empty when
// no scenario has a breakdown.
std::vector<std::pair<std::string, std::string>> breakdown_pgfplots(const BreakdownResults& results);

}  // namespace m2mlat::report
