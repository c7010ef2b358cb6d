// What `pair`, `stats` and `export` read: campaign stores (every scenario in them) and data files
// (one scenario each, named after the file), or an explicit cause file and effect file.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/cli/analysis_options.hpp"

namespace m2mlat::cli {

struct InputFlags {
  std::vector<std::string> inputs;     // stores (SQLite files) or data files
  std::vector<std::string> scenarios;  // only these scenarios of the stores
  std::string cause_file, effect_file;
  std::string format;    // data file format; empty = detect
  bool rematch = false;  // re-pair a paired-results CSV instead of using its rows as pairs
  void add_to(CLI::App& sub, bool allow_rematch);
};

// True if the file is an SQLite database (store::is_sqlite_database: safe beside open connections).
bool is_sqlite_file(const std::string& path);

// Loads and analyses every selected scenario. Throws core::Error naming file, line or scenario.
std::vector<analysis::ScenarioResult> analyse_inputs(const InputFlags& inputs,
                                                     const SelectionFlags& selection, const MatchFlags& match,
                                                     const StatsFlags& stats);

}  // namespace m2mlat::cli
