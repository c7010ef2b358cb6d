// The report as JSON, format "m2mlat-report/1" (docs/report.md): every scenario in the layout of
// m2mlat-stats/1 plus its group, uncertainty and losses; every comparison with its intervals, tests
// and sentence; and the command and versions that produced it.
#pragma once

#include <nlohmann/json.hpp>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

inline constexpr const char* kReportFormat = "m2mlat-report/1";

nlohmann::json comparison_json(const ComparisonReport& comparison);
nlohmann::json report_document(const Report& report);

}  // namespace m2mlat::report
