// The stage breakdown's flags of `stats` and `report` (docs/breakdown.md): the markers (m2mlat-markers/1
// files, repeatable), the stage rule (a stages file), and where the per-event rows go. Applied to
// the pipeline's results after the analysis.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::cli {

struct BreakdownFlags {
  std::vector<std::string> marker_files;
  std::string stages_file;
  std::string csv_file;  // per-event stage rows (m2mlat-breakdown/1); empty: none
  void add_to(CLI::App& sub);
  bool given() const { return !stages_file.empty(); }
  // Reads the rule and the markers, then sets each result's breakdown. Nothing when no rule was
  // given; core::Error(usage) for markers without a rule or a rule without markers, and the
  // readers' errors naming the file and line.
  void apply(std::vector<analysis::ScenarioResult>& results) const;
  // Writes the per-event rows when --breakdown-csv was given.
  void write_csv(std::span<const analysis::ScenarioResult> results) const;
};

}  // namespace m2mlat::cli
