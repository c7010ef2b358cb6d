// What a confidence interval's bootstrap resampled, in words: shown beside every interval.
#pragma once

#include <string>

#include "m2mlat/stats/bootstrap.hpp"

namespace m2mlat::report {

// "the 55 manoeuvres resampled whole (1-9 pairs each: ...)", "blocks of 4 consecutive pairs ...", or
// "the 64 pairs resampled one by one: ..." (docs/statistics.md, "What is resampled").
std::string resampling_text(const stats::Resampling& r);
// A short name for a table cell: "pairs", "manoeuvres", "blocks of 4 pairs", "blocks of 3 manoeuvres".
std::string resampling_name(const stats::Resampling& r);

}  // namespace m2mlat::report
