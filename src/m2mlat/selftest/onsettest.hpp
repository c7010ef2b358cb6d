// The onset test: each onset detector's error measured against the simulator's truth, over motions
// from slow to fast (an operator's hand, the vehicle's actuator) and in the baseline setting (two
// gyroscopes on one rigid body, true M2M = 0). The figures `m2mlat onsettest` prints and
// docs/onset.md tabulates: the measured onset term an inertial source brings to the error budget.
//
// Each motion is simulated on its own trace: still for 0.3..0.6 s, the motion, still for 0.3 s. Hand
// motions peak at a rate drawn uniformly within the speed class and last 0.4..1.2 s; the actuator
// answers each hand motion after 50..150 ms within its limits (sim/gyro_motion.hpp). Errors are
// detected - true, ns: positive is late.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/sim/gyro.hpp"

namespace m2mlat::selftest {

struct SpeedClass {
  std::string_view name;
  double min_deg_s = 0, max_deg_s = 0;  // the hand's peak rate, deg/s
};
inline constexpr std::array kSpeedClasses{SpeedClass{"slow", 20, 50}, SpeedClass{"medium", 50, 150},
                                          SpeedClass{"fast", 150, 400}};

struct OnsetTestOptions {
  std::uint64_t seed = 1;
  int motions = 100;  // per speed class
  sim::GyroConfig gyro;
  sim::ActuatorLimits actuator;
  sim::RateMotion::Shape hand_shape = sim::RateMotion::Shape::minimum_jerk;  // the operator's hand
  std::vector<std::string> detectors{"reference", "flank"};
};

// The spread of a set of errors, ns; NaN when there are none.
struct ErrorSpread {
  std::size_t n = 0;
  double median_ns = 0, p5_ns = 0, p95_ns = 0;
  double abs_p95_ns = 0;  // 95th percentile of |error|
};
ErrorSpread error_spread(std::vector<double> errors_ns);

struct OnsetRow {
  std::string detector, profile, speed;  // profile: "hand" or "actuator"
  std::size_t motions = 0;               // true motions
  std::size_t found = 0;                 // matched by a detected motion
  std::size_t extra = 0;                 // detected motions matching no true one
  ErrorSpread onset, end;
  double median_stated_sd_ns = 0;  // the detector's own onset uncertainty, median
  double within_2sd_share = 0;     // share of found onsets within 2 stated sd of the truth
};

struct BaselineRow {
  std::string detector, speed;
  std::size_t pairs = 0;
  ErrorSpread m2m;  // onset on chip B - onset on chip A (true M2M = 0)
};

struct OnsetTestResult {
  OnsetTestOptions options;
  std::vector<OnsetRow> rows;
  std::vector<BaselineRow> baseline;
  std::uint64_t samples = 0;                                  // samples simulated (every trace)
  std::vector<std::pair<std::string, double>> samples_per_s;  // per detector, this machine
};

// Throws core::Error(usage) for an unknown detector or a motion count below 1.
OnsetTestResult run_onsettest(const OnsetTestOptions& options);
nlohmann::json onsettest_json(const OnsetTestResult& result);  // m2mlat-onsettest/1
std::string onsettest_text(const OnsetTestResult& result);

}  // namespace m2mlat::selftest
