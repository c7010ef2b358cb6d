#include "m2mlat/onset/motion.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/core/error.hpp"

namespace m2mlat::onset {

void check_trace(const core::RateTrace& trace) {
  if (!std::isfinite(trace.counts_per_deg_s) || trace.counts_per_deg_s <= 0)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("rate trace: counts_per_deg_s is {}: it must be a positive number "
                                  "(e.g. 131 for an MPU-6050 at +-250 deg/s)",
                                  trace.counts_per_deg_s));
  const auto& s = trace.samples;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i].bound_ns < 0)
      throw core::Error(core::ErrorKind::data, fmt::format("rate trace: sample {} (time_ns {}): bound_ns is "
                                                           "negative ({})",
                                                           i, s[i].time_ns, s[i].bound_ns));
    if (i > 0 && s[i].time_ns <= s[i - 1].time_ns)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("rate trace: sample {} (time_ns {}) is not after sample {} (time_ns {}): "
                                    "samples must be in strictly increasing time order",
                                    i, s[i].time_ns, i - 1, s[i - 1].time_ns));
  }
}

}  // namespace m2mlat::onset
