// Comparisons in words and in a terminal table: the plain-language line per comparison
// ("static_5g vs static_wifi: IQR 47 % narrower (95 % CI 21 to 62 %), p = 0.004 (Brown-Forsythe);
// median +56.1 ms (95 % CI 12.0 to 81.5 ms), p = 0.02 (Mann-Whitney) ..."), with a note when a
// difference is smaller than the measurement uncertainty.
#pragma once

#include <span>
#include <string>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

// "p = 0.0023", "p < 0.0001".
std::string p_text(double p);
// The plain-language line of one comparison (no trailing newline).
std::string comparison_sentence(const ComparisonReport& c);
// The notes of a comparison: differences smaller than the measurement uncertainty; empty if none.
std::string uncertainty_note(const ComparisonReport& c);
// One row per comparison: medians, difference and CI, IQR ratio and CI, SD ratio and CI, both p values.
std::string comparison_table(std::span<const ComparisonReport> comparisons);

}  // namespace m2mlat::report
