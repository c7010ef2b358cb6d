// Step detection from realtime - monotonic_raw between readings.
#include "m2mlat/sync/step_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

namespace m2mlat::sync {

std::optional<Step> StepDetector::observe(const ClockPair& pair, double rate_ppm) {
  std::optional<Step> step;
  if (last_) {
    const std::int64_t elapsed_raw = pair.monotonic_raw_ns - last_->pair.monotonic_raw_ns;
    const std::int64_t change =
        (pair.realtime_ns - pair.monotonic_raw_ns) - (last_->pair.realtime_ns - last_->pair.monotonic_raw_ns);
    // The rate may have changed between the readings: allow the larger of the two, plus the
    // tolerance, plus the uncertainty of both pairings. Floating point only for this allowance.
    const double ppm = std::max(std::fabs(rate_ppm), std::fabs(last_->rate_ppm)) + options_.tolerance_ppm;
    const auto explained =
        static_cast<std::int64_t>(std::ceil(static_cast<double>(std::llabs(elapsed_raw)) * ppm / 1e6)) +
        (pair.window_ns + last_->pair.window_ns) / 2;
    const std::int64_t unexplained = std::llabs(change) - explained;
    if (unexplained > options_.threshold.count()) {
      Step s;
      s.to_ns = pair.realtime_ns;
      s.from_ns = last_->pair.realtime_ns + elapsed_raw;
      s.step_ns = s.to_ns - s.from_ns;
      s.unexplained_ns = unexplained;
      step = s;
    }
  }
  last_ = Last{pair, rate_ppm};
  return step;
}

store::ClockSample step_sample(const Step& step) {
  store::ClockSample sample;
  sample.time = core::TimePoint::from_ns(core::Clock::realtime, step.to_ns);
  sample.source = "step";
  sample.offset_ns = step.step_ns;
  sample.max_error_ns = std::llabs(step.step_ns);
  sample.est_error_ns = std::llabs(step.step_ns);
  sample.synchronised = false;
  sample.detail_json = nlohmann::json{{"from_ns", step.from_ns},
                                      {"to_ns", step.to_ns},
                                      {"step_ns", step.step_ns},
                                      {"unexplained_ns", step.unexplained_ns}}
                           .dump();
  return sample;
}

}  // namespace m2mlat::sync
