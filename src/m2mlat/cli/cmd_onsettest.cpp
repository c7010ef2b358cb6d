// `m2mlat onsettest`: each onset detector's bias and spread against the simulator's truth, over
// motions from slow to fast and in the baseline setting (selftest/onsettest.hpp).
#include <fmt/format.h>

#include <memory>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/selftest/onsettest.hpp"
#include "m2mlat/sim/gyro_motion.hpp"

namespace m2mlat::cli {

Runner attach_onsettest(CLI::App& sub) {
  auto c = std::make_shared<selftest::OnsetTestOptions>();
  auto json = std::make_shared<bool>(false);
  auto hand_shape = std::make_shared<std::string>("minimum-jerk");
  sub.add_option("--seed", c->seed, "Seed of the simulated motions and chips")->capture_default_str();
  sub.add_option("--motions", c->motions, "Simulated motions per speed class")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub.add_option("--detector", c->detectors, "Detectors to measure (reference, flank)")
      ->capture_default_str();
  sub.add_option("--noise-density", c->gyro.noise_density_deg_s_rthz,
                 "Gyro rate noise density, deg/s/sqrt(Hz)")
      ->capture_default_str();
  sub.add_option("--bias-sd", c->gyro.bias_sd_deg_s, "Per-axis bias drawn per chip, sd, deg/s")
      ->capture_default_str();
  sub.add_option("--period-ns", c->gyro.period_ns, "Gyro sample period, ns")->capture_default_str();
  sub.add_option("--hand-shape", *hand_shape,
                 "The simulated hand's rate curve: minimum-jerk, or raised-cosine (no polynomial: checks "
                 "that a detector's figures do not come from its model matching the simulated curve)")
      ->capture_default_str();
  sub.add_flag("--json", *json, "Print m2mlat-onsettest/1 JSON");
  return [c, json, hand_shape] {
    c->hand_shape = sim::parse_hand_shape(*hand_shape);
    const auto r = selftest::run_onsettest(*c);
    if (*json)
      print_json(selftest::onsettest_json(r));
    else
      fmt::print("{}", selftest::onsettest_text(r));
    return 0;
  };
}

}  // namespace m2mlat::cli
