// Every parameter of the simulated rig, in one value type. A default-constructed RigConfig is the
// "static_wifi" scenario (the embedded default); presets.hpp names the others and overrides.hpp sets
// single fields from text. Units are in the names or comments: durations are core::Duration (int64
// ns), angles are degrees, rates are ppm, probabilities are in [0, 1].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/core/time.hpp"
#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/distribution.hpp"
#include "m2mlat/sim/network.hpp"

namespace m2mlat::sim {

// The operator's manoeuvres. The wheel rests on one side of the sensor, with every magnet on that
// side; a manoeuvre turns it across the sensor, so each magnet passes once, to rest on the other
// side (or, with return_probability, across and back to where it started: each magnet passes twice).
struct MotionConfig {
  core::Duration interval_min =
      std::chrono::milliseconds(1500);  // start-to-start time between manoeuvres: uniform in
  core::Duration interval_max = std::chrono::milliseconds(4000);  // [min, max), never periodic
  core::Duration min_pause =
      std::chrono::milliseconds(200);  // the wheel rests at least this long between manoeuvres
  double speed_min_deg_s = 150;        // the operator's turning speed: uniform in [min, max), deg/s
  double speed_max_deg_s = 400;
  double clearance_min_deg = 5;   // where the wheel stops past the outermost magnet: uniform in
  double clearance_max_deg = 45;  // [min, max), degrees
  double return_probability = 0;  // chance that a manoeuvre turns across and straight back
  core::Duration hold_min =
      std::chrono::milliseconds(150);  // pause before the return sweep: uniform in [min, max)
  core::Duration hold_max = std::chrono::milliseconds(600);

  friend bool operator==(const MotionConfig&, const MotionConfig&) = default;
};

// The operator station: it samples the wheel and sends the angle every command period.
struct StationConfig {
  core::Duration command_period = std::chrono::milliseconds(20);  // 50 Hz command stream
  DurationDist processing = normal(std::chrono::milliseconds(3), std::chrono::milliseconds(1),
                                   std::chrono::microseconds(500));  // sample -> packet on the wire

  friend bool operator==(const StationConfig&, const StationConfig&) = default;
};

// The vehicle: its control loop executes the newest command every control period, and the steering
// actuator starts to move after a dead time that is longer when the vehicle stands still (tyre
// scrub, no self-aligning help) than when it rolls. The actuator then turns at its own speed.
struct VehicleConfig {
  double moving_probability = 0;  // chance the vehicle is driving during a manoeuvre
  core::Duration control_period = std::chrono::milliseconds(10);  // the drive-by-wire loop
  DurationDist execution = normal(std::chrono::milliseconds(2), std::chrono::microseconds(500),
                                  std::chrono::microseconds(200));  // command received -> actuator set point
  DurationDist actuator_lag_static =
      normal(std::chrono::milliseconds(770), std::chrono::milliseconds(72),
             std::chrono::milliseconds(350));  // set point -> wheel moves, standing
  DurationDist actuator_lag_moving = normal(std::chrono::milliseconds(640), std::chrono::milliseconds(100),
                                            std::chrono::milliseconds(250));  // the same, driving
  double speed_ratio_min = 0.6;   // the vehicle wheel turns at the operator's speed times a ratio
  double speed_ratio_max = 0.95;  // uniform in [min, max) ...
  double max_speed_deg_s = 360;   // ... but never faster than the actuator can, deg/s
  core::Duration min_pause =
      std::chrono::milliseconds(50);  // a sweep starts at least this long after the previous one ended

  friend bool operator==(const VehicleConfig&, const VehicleConfig&) = default;
};

// One Hall sensor (A3144: a falling edge when a magnet passes) and the board's edge timestamping.
struct SensorConfig {
  double miss_probability = 0;    // chance a magnet pass gives no edge
  double bounce_probability = 0;  // chance a detected pass gives 1..bounce_max_extra more edges
  int bounce_max_extra = 3;       // most extra edges of one bounce
  core::Duration bounce_window =
      std::chrono::milliseconds(3);  // the extra edges come within this time after the true edge
  core::Duration bounce_min_gap =
      std::chrono::microseconds(50);  // ... each at least this long after the previous edge
  double spurious_per_minute = 0;     // edges from nowhere (interference), a Poisson process
  // edge -> kernel timestamp in the hard IRQ: 2 us + exponential, mean 3 us, at most 1 ms
  DurationDist irq_latency = {
      Shape::exponential, std::chrono::microseconds(2), std::chrono::microseconds(3), 0,
      core::Duration{0},  std::chrono::milliseconds(1)};

  friend bool operator==(const SensorConfig&, const SensorConfig&) = default;
};

// A sensor as fitted in the field: 1% missed passes, 3% bounces, a spurious edge every 5 minutes.
SensorConfig field_sensor();

struct RigConfig {
  std::string scenario = "static_wifi";  // the preset this started from (for reports); free text
  std::uint64_t seed = 1;
  std::string cause_node = "operator";
  std::string effect_node = "vehicle";
  std::string channel = "wheel";
  core::TimePoint start =
      core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'000);  // 2026-06-01T09:00:00Z
  std::int64_t manoeuvres = 70;  // stop after this many manoeuvres (0: no limit) ...
  core::Duration duration{0};    // ... or when the next would start this long after `start` (0: no limit)
  std::vector<double> magnets_deg = {0};  // magnet positions on the wheel, degrees in [0, 360); both wheels

  MotionConfig motion;
  StationConfig station;
  NetworkProfile network = network_profile("wifi");
  VehicleConfig vehicle;
  SensorConfig cause_sensor = field_sensor();
  SensorConfig effect_sensor = field_sensor();
  // Two boards' crystals a few ppm apart; the vehicle's sync path is slightly asymmetric.
  ClockConfig cause_clock = {core::Duration{0}, 3.2, 0.002, std::chrono::microseconds(50)};
  ClockConfig effect_clock = {core::Duration{0}, -5.1, 0.002, std::chrono::microseconds(150)};
  SyncConfig sync = sync_profile("co_referenced");
  core::Duration clock_sample_interval =
      std::chrono::seconds(10);  // record both clocks' state this often (0: never)

  friend bool operator==(const RigConfig&, const RigConfig&) = default;
};

// Throws core::Error(usage) naming the first field that is out of range or inconsistent.
void validate(const RigConfig& config);

// Sets every miss, bounce and spurious-edge probability of both sensors to zero.
void clear_imperfections(RigConfig& config);

}  // namespace m2mlat::sim
