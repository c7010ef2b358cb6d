// The range checks of the options the onset detectors share (the rest level they learn, the smoothed
// magnitude they detect on): one rule for the flank and the streaming detector.
#pragma once

#include <fmt/format.h>

#include <string_view>

#include "m2mlat/core/error.hpp"

namespace m2mlat::onset {

// Throws core::Error(usage) "<detector>: <field> = <value> is out of range".
[[noreturn]] inline void option_out_of_range(std::string_view detector, std::string_view field, double value) {
  throw core::Error(core::ErrorKind::usage, fmt::format("{}: {} = {} is out of range", detector, field, value));
}

// learn_ns, max_rest_sd_deg_s, max_bias_deg_s, rest_alpha, smooth_alpha, k and quiet_ns of `o`.
template <class Options>
void check_rest_options(std::string_view detector, const Options& o) {
  const auto bad = [&](std::string_view field, double value) { option_out_of_range(detector, field, value); };
  if (o.learn_ns <= 0) bad("learn_ns", static_cast<double>(o.learn_ns));
  if (!(o.max_rest_sd_deg_s > 0)) bad("max_rest_sd_deg_s", o.max_rest_sd_deg_s);
  if (!(o.max_bias_deg_s >= 0)) bad("max_bias_deg_s", o.max_bias_deg_s);
  if (!(o.rest_alpha > 0 && o.rest_alpha <= 1)) bad("rest_alpha", o.rest_alpha);
  if (!(o.smooth_alpha > 0 && o.smooth_alpha <= 1)) bad("smooth_alpha", o.smooth_alpha);
  if (!(o.k > 0)) bad("k", o.k);
  if (o.quiet_ns <= 0) bad("quiet_ns", static_cast<double>(o.quiet_ns));
}

}  // namespace m2mlat::onset
