// Step detection from realtime - monotonic_raw between readings.
#include "m2mlat/sync/step_detector.hpp"

#include "m2mlat/store/clock_step.hpp"

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
      s.explained_ns = explained;
      s.elapsed_ns = elapsed_raw;
      step = s;
    }
  }
  last_ = Last{pair, rate_ppm};
  return step;
}

store::ClockSample step_sample(const Step& step) {
  store::ClockStep record;
  record.at_ns = step.to_ns;
  record.earliest_ns = step.to_ns - std::max<std::int64_t>(step.elapsed_ns, 0) - step.explained_ns;
  record.size_ns = step.step_ns;
  record.size_max_ns = step.explained_ns;
  record.size_est_ns = (step.explained_ns + 1) / 2;
  record.origin = "monitor";
  store::ClockSample sample = store::step_clock_sample(record);
  auto detail = nlohmann::json::parse(sample.detail_json);
  detail["unexplained_ns"] = step.unexplained_ns;
  sample.detail_json = detail.dump();
  return sample;
}

}  // namespace m2mlat::sync
