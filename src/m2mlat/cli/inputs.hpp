// What `pair`, `stats`, `report` and `export` read: campaign stores (every scenario in them) and data
// files (one scenario each, named after the file), or an explicit cause file and effect file. The
// flags only; analysis::analyse_inputs (analysis/pipeline.hpp) reads and analyses them.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "m2mlat/analysis/pipeline.hpp"

namespace m2mlat::cli {

struct InputFlags {
  std::vector<std::string> inputs;     // stores (SQLite files) or data files
  std::vector<std::string> scenarios;  // only these scenarios of the stores
  std::string cause_file, effect_file;
  std::string format;    // data file format; empty = detect
  bool rematch = false;  // re-pair a paired-results CSV instead of using its rows as pairs
  void add_to(CLI::App& sub, bool allow_rematch);
  analysis::PipelineInputs pipeline_inputs() const;  // throws core::Error(usage) for an unknown --format
};

// True if the file is an SQLite database (store::is_sqlite_database: safe beside open connections).
bool is_sqlite_file(const std::string& path);

}  // namespace m2mlat::cli
