// Validation of a rig configuration, and the field sensor's imperfections.
#include "m2mlat/sim/rig_config.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly

namespace m2mlat::sim {

using namespace std::chrono_literals;

namespace {
[[noreturn]] void fail(std::string_view field, std::string_view what) {
  throw core::Error(core::ErrorKind::usage, fmt::format("simulator setting '{}': {}", field, what));
}

void check_probability(double p, std::string_view field) {
  if (!(p >= 0 && p <= 1)) fail(field, "must be a probability in [0, 1]");
}

void check_range(core::Duration lo, core::Duration hi, std::string_view field) {
  if (lo.count() < 0) fail(field, "must not be negative");
  if (lo > hi) fail(field, "min is larger than max");
}

void validate_sensor(const SensorConfig& sensor, std::string_view field) {
  check_probability(sensor.miss_probability, fmt::format("{}.miss_probability", field));
  check_probability(sensor.bounce_probability, fmt::format("{}.bounce_probability", field));
  if (sensor.bounce_max_extra < 1 || sensor.bounce_max_extra > 20)
    fail(fmt::format("{}.bounce_max_extra", field), "must be in 1..20");
  if (sensor.bounce_min_gap < 1us) fail(fmt::format("{}.bounce_min_gap", field), "must be at least 1us");
  if (sensor.bounce_window < sensor.bounce_min_gap * sensor.bounce_max_extra || sensor.bounce_window > 100ms)
    fail(fmt::format("{}.bounce_window", field), "must hold bounce_max_extra gaps and be at most 100ms");
  if (!(sensor.spurious_per_minute >= 0 && sensor.spurious_per_minute <= 6000))
    fail(fmt::format("{}.spurious_per_minute", field), "must be in [0, 6000]");
  validate(sensor.irq_latency, fmt::format("{}.irq_latency", field));
  validate(sensor.dwell, fmt::format("{}.dwell", field));
  if (sensor.dwell.min <= sensor.bounce_window)
    fail(fmt::format("{}.dwell", field),
         "min must be longer than bounce_window: a pass is released after its bounces");
  validate(sensor.interference_width, fmt::format("{}.interference_width", field));
  if (sensor.interference_width.min.count() < 1)
    fail(fmt::format("{}.interference_width", field), "min must be at least 1ns");
  if (sensor.irq_latency.min.count() < 0 || sensor.irq_latency.max > 10ms)
    fail(fmt::format("{}.irq_latency", field), "must lie within [0, 10ms]");
}
// After a stall the queue drains faster than the station sends, and the vehicle's loop sees every
// rest of the operator's wheel (at least one control period of drained packets holds it): so no
// sweep is skipped by a jump to a newer angle, and each vehicle pass stays the effect of exactly one
// operator pass (docs/simulator.md, "Network stalls").
void validate_stalls(const RigConfig& config) {
  const auto period = config.station.command_period;
  const auto drain = config.network.stall_drain;
  if (drain >= period) fail("network.stall_drain", "must be shorter than station.command_period");
  auto seen = [&](core::Duration rest, std::string_view field) {
    if ((rest / period) * drain < config.vehicle.control_period)
      fail(field, fmt::format("with stalls, a rest of {} ns drains in less than one control period, so the "
                              "vehicle would skip a sweep; lengthen it or network.stall_drain",
                              rest.count()));
  };
  seen(config.motion.min_pause, "motion.min_pause");
  if (config.motion.return_probability > 0) seen(config.motion.hold_min, "motion.hold_min");
}
}  // namespace

double clearance_max_deg(const MotionConfig& motion, double span_deg) {
  return std::min(motion.clearance_max_deg, kClearanceShareOfGap * (360 - span_deg) / 2);
}

SensorConfig field_sensor() {
  SensorConfig sensor;
  sensor.miss_probability = 0.01;
  sensor.bounce_probability = 0.03;
  sensor.spurious_per_minute = 0.2;
  return sensor;
}

void validate(const RigConfig& config) {
  if (config.cause_node.empty() || config.effect_node.empty() || config.channel.empty())
    fail("cause_node/effect_node/channel", "names must not be empty");
  if (config.cause_node == config.effect_node) fail("effect_node", "must differ from cause_node");
  if (config.start.clock() != core::Clock::realtime) fail("start", "must be a CLOCK_REALTIME time");
  if (config.start.ns() < 0 || config.start.ns() > 4'000'000'000'000'000'000)
    fail("start", "must be in 1970..2096");
  if (config.manoeuvres < 0) fail("manoeuvres", "must not be negative");
  if (config.duration.count() < 0) fail("duration", "must not be negative");
  if (config.manoeuvres == 0 && config.duration.count() == 0)
    fail("manoeuvres", "set a number of manoeuvres or a duration (both are 0)");
  if (config.duration > std::chrono::hours(24 * 365 * 20)) fail("duration", "must be at most 20 years");

  if (config.magnets_deg.empty() || config.magnets_deg.size() > 36)
    fail("magnets_deg", "needs 1..36 magnets");
  for (double angle : config.magnets_deg)
    if (!(angle >= 0 && angle < 360)) fail("magnets_deg", "angles must be in [0, 360)");
  auto sorted = config.magnets_deg;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    fail("magnets_deg", "angles must differ");
  const double span = sorted.back() - sorted.front();

  const auto& m = config.motion;
  check_range(m.interval_min, m.interval_max, "motion.interval_min");
  if (m.interval_max <= 0ns) fail("motion.interval_max", "must be positive");
  if (m.min_pause.count() < 0) fail("motion.min_pause", "must not be negative");
  if (!(m.speed_min_deg_s >= 1 && m.speed_min_deg_s <= m.speed_max_deg_s && m.speed_max_deg_s <= 3600))
    fail("motion.speed_min_deg_s", "speeds must satisfy 1 <= min <= max <= 3600 deg/s");
  if (!(m.clearance_min_deg > 0 && m.clearance_min_deg <= m.clearance_max_deg))
    fail("motion.clearance_min_deg", "clearances must satisfy 0 < min <= max");
  // A sweep must not bring a magnet round to the sensor a second time: the draws are capped (see
  // clearance_max_deg()), so only a minimum that leaves no room is refused.
  if (!(m.clearance_min_deg < clearance_max_deg(m, span)))
    fail("motion.clearance_min_deg",
         fmt::format("the magnets span {} degrees, so the wheel can rest at most {} degrees past the "
                     "outermost magnet; clearance_min_deg must stay below that",
                     span, clearance_max_deg(m, span)));
  check_probability(m.return_probability, "motion.return_probability");
  check_range(m.hold_min, m.hold_max, "motion.hold_min");

  if (config.station.command_period < 100us || config.station.command_period > 10s)
    fail("station.command_period", "must be between 100us and 10s");
  validate(config.station.processing, "station.processing");
  validate(config.network, "network");

  const auto& v = config.vehicle;
  check_probability(v.moving_probability, "vehicle.moving_probability");
  if (v.control_period < 100us || v.control_period > 10s)
    fail("vehicle.control_period", "must be between 100us and 10s");
  validate(v.execution, "vehicle.execution");
  validate(v.actuator_lag_static, "vehicle.actuator_lag_static");
  validate(v.actuator_lag_moving, "vehicle.actuator_lag_moving");
  if (!(v.speed_ratio_min > 0 && v.speed_ratio_min <= v.speed_ratio_max && v.speed_ratio_max <= 10))
    fail("vehicle.speed_ratio_min", "ratios must satisfy 0 < min <= max <= 10");
  if (!(v.max_speed_deg_s >= 1 && v.max_speed_deg_s <= 3600))
    fail("vehicle.max_speed_deg_s", "must be in [1, 3600]");
  if (v.min_pause.count() < 0) fail("vehicle.min_pause", "must not be negative");
  if (config.network.stall_per_minute > 0) validate_stalls(config);

  validate_sensor(config.cause_sensor, "cause_sensor");
  validate_sensor(config.effect_sensor, "effect_sensor");
  validate(config.cause_clock, "cause_clock");
  validate(config.effect_clock, "effect_clock");
  validate(config.sync, "sync");
  if (config.clock_sample_interval.count() < 0) fail("clock_sample_interval", "must not be negative");
  if (config.clock_sample_interval.count() > 0 && config.clock_sample_interval < 1ms)
    fail("clock_sample_interval", "must be 0 (off) or at least 1ms");
}

void clear_imperfections(RigConfig& config) {
  for (SensorConfig* sensor : {&config.cause_sensor, &config.effect_sensor}) {
    sensor->miss_probability = 0;
    sensor->bounce_probability = 0;
    sensor->spurious_per_minute = 0;
  }
}

}  // namespace m2mlat::sim
