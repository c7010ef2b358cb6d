// A statistic as a JSON number: NaN (undefined, e.g. the SD of one sample) becomes null. Shared by
// every JSON output of figures (report, selftest).
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

namespace m2mlat::formats {

inline nlohmann::json number(double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); }
inline nlohmann::json number(const std::optional<double>& x) { return x ? number(*x) : nlohmann::json(nullptr); }

}  // namespace m2mlat::formats
