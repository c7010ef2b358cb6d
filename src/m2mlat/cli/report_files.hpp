// What `report` and `demo --report` share: a report's comparisons and its folder of files.
#pragma once

#include <string>
#include <vector>

#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/report/report_model.hpp"

namespace m2mlat::cli {

// An empty report with the command line as typed (shell-quoted, from /proc/self/cmdline) and the
// versions of m2mlat, its compiler and libraries.
report::Report new_report();

// Compares the scenarios given as SUBJECT:BASELINE (a malformed one is a usage error), or with none
// given and !no_compare the report's default pairs (report_model.hpp: within each group, each later
// scenario against each earlier one, or every other one against `baseline` when given; a scenario with
// fewer than 2 latencies is skipped with a warning) and the full-loop files among themselves, quantity
// by quantity.
void add_comparisons(report::Report& r, const std::vector<std::string>& compares, bool no_compare,
                     const StatsFlags& stats, const std::string& baseline = {});

// report.html, report.md, report.json, scenarios.csv, comparisons.csv, full_loop.csv (when there are
// full-loop results) and pgfplots/ in `dir` (created if missing).
void write_report_folder(const report::Report& r, const std::string& dir);

}  // namespace m2mlat::cli
