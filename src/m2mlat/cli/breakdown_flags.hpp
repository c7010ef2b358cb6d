// The stage breakdown's flags of `stats` and `report` (docs/breakdown.md): the markers (m2mlat-markers/1
// files, repeatable, and the markers table of every store analysed), the stage rule (a stages file),
// and where the per-event rows go. Applied to the pipeline's results after the analysis.
#pragma once

#include <CLI/CLI.hpp>
#include <span>
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
  // Reads the rule, the marker files and the markers stored in `inputs`' stores (the other inputs
  // are data files, skipped), then sets each result's breakdown. Nothing when no rule was given;
  // core::Error(usage) for marker files without a rule or a rule without any marker, and the
  // readers' errors naming the file and line.
  void apply(std::vector<analysis::ScenarioResult>& results, std::span<const std::string> inputs) const;
  // Writes the per-event rows when --breakdown-csv was given.
  void write_csv(std::span<const analysis::ScenarioResult> results) const;
};

}  // namespace m2mlat::cli
