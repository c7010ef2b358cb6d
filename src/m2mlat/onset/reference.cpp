#include "m2mlat/onset/reference.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/uncertainty.hpp"

namespace m2mlat::onset {

Detection detect_reference(const core::RateTrace& trace, const ReferenceOptions& options) {
  check_trace(trace);
  if (!(options.alpha > 0 && options.alpha <= 1))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("reference detector: alpha {} is not in (0, 1]", options.alpha));
  if (!(options.threshold_deg_s > 0))
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("reference detector: threshold_deg_s {} is not positive", options.threshold_deg_s));
  if (options.rearm_samples < 0)
    throw core::Error(core::ErrorKind::usage, "reference detector: rearm_samples is negative");

  Detection out;
  const auto& s = trace.samples;
  if (s.empty()) return out;
  const double scale = 1.0 / trace.counts_per_deg_s;
  const double threshold2 = options.threshold_deg_s * options.threshold_deg_s;
  double e[3];
  for (int a = 0; a < 3; ++a) e[a] = s[0].raw[static_cast<std::size_t>(a)] * scale;

  enum class State { armed, moving, still } state = State::armed;
  std::int64_t still = 0;
  Motion current;
  for (std::size_t i = 0; i < s.size(); ++i) {
    double m2 = 0;
    for (std::size_t a = 0; a < 3; ++a) {
      e[a] += options.alpha * (s[i].raw[a] * scale - e[a]);
      m2 += e[a] * e[a];
    }
    const bool above = m2 > threshold2;
    if (i == 0 && above) {
      out.began_in_motion = true;
      state = State::still;
      continue;
    }
    switch (state) {
      case State::armed:
        if (above) {
          current = Motion{};
          current.onset_ns = s[i].time_ns;
          current.onset_sd_ns = crossing_sd_ns(s, i);
          current.peak_deg_s = std::sqrt(m2);
          state = State::moving;
        }
        break;
      case State::moving:
        if (above) {
          current.peak_deg_s = std::max(current.peak_deg_s, std::sqrt(m2));
        } else {
          current.end_ns = s[i].time_ns;
          current.end_sd_ns = crossing_sd_ns(s, i);
          out.motions.push_back(current);
          state = State::still;
          still = 1;
        }
        break;
      case State::still: still = above ? 0 : still + 1; break;
    }
    if (state == State::still && still >= options.rearm_samples) state = State::armed;
  }
  if (state == State::moving) {
    current.end_ns = s.back().time_ns;
    current.ended = false;
    out.motions.push_back(current);
  }
  return out;
}

}  // namespace m2mlat::onset
