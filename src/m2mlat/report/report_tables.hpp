// The report as tables for people and spreadsheets: plain text for the terminal, Markdown, and CSV
// (one file of scenarios, one of comparisons, one of the full-loop files; columns in docs/report.md).
#pragma once

#include <span>
#include <string>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

std::string report_text(const Report& report);
std::string report_markdown(const Report& report);
std::string scenarios_csv(const Report& report);
std::string comparisons_csv(const Report& report);
// The full-loop files, one row per file and quantity: scenario,file,quantity,events,n,
// excluded_missing,excluded_impossible,excluded_overflow,mean_ms,sd_ms,min_ms,p5_ms,q1_ms,median_ms,
// q3_ms,p90_ms,p95_ms,p99_ms,iqr_ms,max_ms, then above_<t>_fraction per threshold (docs/report.md).
std::string full_loop_csv(std::span<const analysis::FullLoopResult> results);

}  // namespace m2mlat::report
