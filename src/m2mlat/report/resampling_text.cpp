// The resampling plan of a bootstrap as a sentence and as a name.
#include "m2mlat/report/resampling_text.hpp"

#include <fmt/format.h>

namespace m2mlat::report {

std::string resampling_name(const stats::Resampling& r) {
  const char* unit = r.grouped() ? "manoeuvres" : "pairs";
  if (r.sample_by_sample()) return "pairs";
  if (r.blocks.length == 1) return unit;
  return fmt::format("blocks of {} {}", r.blocks.length, unit);
}

std::string resampling_text(const stats::Resampling& r) {
  const std::string correlation =
      r.blocks.reach == 0
          ? fmt::format("uncorrelated (lag-1 autocorrelation {:.2f})", r.blocks.lag1)
          : fmt::format("correlated up to lag {} (lag-1 autocorrelation {:.2f})", r.blocks.reach, r.blocks.lag1);
  const char* noun = r.grouped() ? "manoeuvres" : "pairs";
  const std::string detail =
      r.grouped() ? fmt::format(" (1-{} pairs each, sharing their manoeuvre's delays)", r.largest_unit)
                  : std::string(" (one a manoeuvre)");
  if (r.over_limit)
    return fmt::format("the {} pairs resampled one by one, although they came as {} {}{}, their latencies {}: "
                       "above {} pairs the units are not resampled, and the interval may be too narrow",
                       r.samples, r.units, noun, detail, correlation, stats::kMaxUnitResampled);
  if (r.sample_by_sample())
    return fmt::format("the {} {}{} resampled one by one, their latencies {}", r.units, noun, detail, correlation);
  if (r.blocks.length == 1)
    return fmt::format("the {} {}{} resampled whole, their latencies {}", r.units, noun, detail, correlation);
  return fmt::format("blocks of {} consecutive {} of the {}{} resampled (circular block bootstrap), their "
                     "latencies {}",
                     r.blocks.length, noun, r.units, detail, correlation);
}

}  // namespace m2mlat::report
