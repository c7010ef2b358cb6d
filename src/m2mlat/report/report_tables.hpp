// The report as tables for people and spreadsheets: plain text for the terminal, Markdown, and CSV
// (one file of scenarios, one of comparisons; columns in docs/report.md).
#pragma once

#include <string>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

std::string report_text(const Report& report);
std::string report_markdown(const Report& report);
std::string scenarios_csv(const Report& report);
std::string comparisons_csv(const Report& report);

}  // namespace m2mlat::report
