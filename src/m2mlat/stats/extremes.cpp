// One pass for the minimum and maximum sample and where they are.
#include "m2mlat/stats/extremes.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

std::optional<Extremes> find_extremes(std::span<const std::int64_t> values_ns,
                                      std::span<const std::int64_t> ids) {
  if (!ids.empty() && ids.size() != values_ns.size()) {
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("find_extremes: {} ids for {} samples", ids.size(), values_ns.size()));
  }
  if (values_ns.empty()) return std::nullopt;
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 1; i < values_ns.size(); ++i) {
    if (values_ns[i] < values_ns[lo]) lo = i;  // strict: the first of equal values stays
    if (values_ns[i] > values_ns[hi]) hi = i;
  }
  const auto make = [&](std::size_t i) {
    return Extreme{values_ns[i], ids.empty() ? static_cast<std::int64_t>(i) : ids[i], i};
  };
  return Extremes{make(lo), make(hi)};
}

}  // namespace m2mlat::stats
