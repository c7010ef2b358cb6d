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

// Shorthands for the defaults below.
using Ms = std::chrono::milliseconds;
using Us = std::chrono::microseconds;

// The operator's manoeuvres. The wheel rests on one side of the sensor, with every magnet on that
// side; a manoeuvre turns it across the sensor, so each magnet passes once, to rest on the other
// side (or, with return_probability, across and back to where it started: each magnet passes twice).
struct MotionConfig {
  // Start-to-start time between manoeuvres: uniform in [min, max), never periodic.
  core::Duration interval_min = Ms{1500};
  core::Duration interval_max = Ms{4000};
  // The wheel rests at least this long between manoeuvres.
  core::Duration min_pause = Ms{200};
  // The operator's turning speed, deg/s: uniform in [min, max) per manoeuvre.
  double speed_min_deg_s = 150;
  double speed_max_deg_s = 400;
  // Where the wheel stops past the outermost magnet, degrees: uniform in [min, max).
  double clearance_min_deg = 5;
  double clearance_max_deg = 45;
  // Chance that a manoeuvre turns across and straight back, after a hold uniform in [min, max).
  double return_probability = 0;
  core::Duration hold_min = Ms{150};
  core::Duration hold_max = Ms{600};

  friend bool operator==(const MotionConfig&, const MotionConfig&) = default;
};

// The operator station: it samples the wheel and sends the angle every command period.
struct StationConfig {
  core::Duration command_period = Ms{20};                   // a 50 Hz command stream
  DurationDist processing = normal(Ms{3}, Ms{1}, Us{500});  // wheel sampled -> packet on the wire

  friend bool operator==(const StationConfig&, const StationConfig&) = default;
};

// The vehicle: its control loop executes the newest command every control period, and the steering
// actuator starts to move after a dead time that is longer when the vehicle stands still (tyre
// scrub, no self-aligning help) than when it rolls. The actuator then turns at its own speed.
struct VehicleConfig {
  double moving_probability = 0;           // chance the vehicle is driving during a manoeuvre
  core::Duration control_period = Ms{10};  // the drive-by-wire loop
  DurationDist execution = normal(Ms{2}, Us{500}, Us{200});  // command picked up -> actuator set point
  // Set point -> the wheel starts to move, standing and driving.
  DurationDist actuator_lag_static = normal(Ms{770}, Ms{72}, Ms{350});
  DurationDist actuator_lag_moving = normal(Ms{640}, Ms{100}, Ms{250});
  // The vehicle's wheel turns at the operator's speed times a ratio uniform in [min, max), but never
  // faster than max_speed_deg_s (deg/s).
  double speed_ratio_min = 0.6;
  double speed_ratio_max = 0.95;
  double max_speed_deg_s = 360;
  // A sweep starts at least this long after the vehicle's previous sweep ended.
  core::Duration min_pause = Ms{50};

  friend bool operator==(const VehicleConfig&, const VehicleConfig&) = default;
};

// One Hall sensor (A3144: a falling edge when a magnet passes) and the board's edge timestamping.
struct SensorConfig {
  double miss_probability = 0;    // chance a magnet pass gives no edge
  double bounce_probability = 0;  // chance a detected pass gives 1..bounce_max_extra more edges
  int bounce_max_extra = 3;
  core::Duration bounce_window = Ms{3};    // the extra edges come within this time after the true one,
  core::Duration bounce_min_gap = Us{50};  // each at least this long after the previous edge
  double spurious_per_minute = 0;          // edges no magnet caused (interference): a Poisson process
  // Edge -> the kernel's timestamp in the hard IRQ: 2 us + exponential with mean 3 us, at most 1 ms.
  DurationDist irq_latency = {Shape::exponential, Us{2}, Us{3}, 0, core::Duration{0}, Ms{1}};
  // The line recorded with both edges (`record --edges both`): each pass a pulse, its rising edge
  // (the line back at idle) `dwell` after the falling one (a field about 5 degrees wide at the
  // steering speeds of a manoeuvre), a bounce's edges alternating, and interference a pulse of
  // `interference_width`. Drawn from a stream of their own: the falling edges stay as without.
  bool both_edges = false;
  DurationDist dwell = normal(Ms{15}, Ms{5}, Ms{5});
  DurationDist interference_width = {Shape::uniform, Us{1}, Us{49}, 0, Us{1}, Ms{1}};  // 1-50 us

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
  // True time of the run's start: 2026-06-01T09:00:00Z.
  core::TimePoint start = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'000);
  // Stop after this many manoeuvres (0: no limit), or when the next would start `duration` after
  // `start` (0: no limit), whichever comes first.
  std::int64_t manoeuvres = 70;
  core::Duration duration{0};
  // Magnet positions on the wheel, degrees in [0, 360); the same on both wheels.
  std::vector<double> magnets_deg = {0};

  MotionConfig motion;
  StationConfig station;
  NetworkProfile network = network_profile("wifi");
  VehicleConfig vehicle;
  SensorConfig cause_sensor = field_sensor();
  SensorConfig effect_sensor = field_sensor();
  // Two boards' crystals a few ppm apart; each sync path slightly asymmetric.
  ClockConfig cause_clock = {core::Duration{0}, 3.2, 0.002, Us{50}};
  ClockConfig effect_clock = {core::Duration{0}, -5.1, 0.002, Us{150}};
  SyncConfig sync = sync_profile("co_referenced");
  core::Duration clock_sample_interval =
      std::chrono::seconds{10};  // record both clocks this often (0: never)

  friend bool operator==(const RigConfig&, const RigConfig&) = default;
};

// Where a wheel rests, at most, past the outermost magnet of a layout spanning `span_deg` degrees:
// motion.clearance_max_deg, but never more than kClearanceShareOfGap of half the free arc, so that
// a sweep (clearance + span + clearance) never brings a magnet round to the sensor again. A layout
// all round the wheel (0,90,180,270) thus just works: each sweep is a turn of almost a whole circle.
inline constexpr double kClearanceShareOfGap = 0.9;
double clearance_max_deg(const MotionConfig& motion, double span_deg);

// Throws core::Error(usage) naming the first field that is out of range or inconsistent.
void validate(const RigConfig& config);

// Sets every miss, bounce and spurious-edge probability of both sensors to zero.
void clear_imperfections(RigConfig& config);

}  // namespace m2mlat::sim
