// The simulator's ground truth: what really happened, kept beside the events so that every later
// stage (pairing, statistics, reports, the sync check) can be tested against it.
//
// True times are on core::Clock::simulated: nanoseconds since the Unix epoch of true time (the time
// a perfect clock would read). They cannot be subtracted from the events' CLOCK_REALTIME timestamps
// by accident: the two clocks differ, and core::TimePoint refuses.
#pragma once

#include <cstdint>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::sim {

// What produced an edge. Names are exported: keep them stable.
enum class EdgeKind : std::uint8_t {
  pass = 0,      // a magnet passing the sensor: the edge the measurement is about
  bounce = 1,    // an extra edge a few ms after a pass's edge (contact bounce)
  spurious = 2,  // an edge no magnet caused (interference)
  release = 3,   // a pass's rising edge, the line back at idle (SensorConfig::both_edges)
};
std::string_view to_string(EdgeKind kind);

// A true time from its nanoseconds since the epoch.
inline core::TimePoint true_time(std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::simulated, ns); }

// The truth about one event; parallel to the node's event list (same index).
struct EventTruth {
  EdgeKind kind = EdgeKind::pass;
  std::int64_t manoeuvre = -1;    // index of the manoeuvre (0-based); -1 for spurious edges
  std::int64_t pass = -1;         // index of the magnet pass (0-based, see PassTruth); -1 for spurious
  std::int32_t magnet = -1;       // index into RigConfig::magnets_deg; -1 for spurious
  core::TimePoint true_time;      // when the edge really happened (Clock::simulated)
  core::Duration irq_latency{0};  // edge -> kernel timestamp
  core::Duration clock_error{0};  // the node's clock reading - true time, when it took the timestamp
  // Always: event.time.ns() == true_time.ns() + irq_latency + clock_error.

  friend bool operator==(const EventTruth&, const EventTruth&) = default;
};

// One magnet passing the sensor of the operator's wheel, and the same magnet passing the vehicle's.
struct PassTruth {
  std::int64_t index = 0;          // 0, 1, 2 ... in order of the operator's pass
  std::int64_t manoeuvre = 0;      // the manoeuvre it belongs to
  std::int32_t sweep = 0;          // 0: the turn across; 1: the return of an across-and-back manoeuvre
  std::int32_t magnet = 0;         // index into RigConfig::magnets_deg
  core::TimePoint cause_time;      // true time of the pass on the operator's wheel (Clock::simulated)
  core::TimePoint effect_time;     // true time of the pass on the vehicle's wheel (Clock::simulated)
  std::int64_t cause_event = -1;   // index of its edge in the cause events; -1: missed
  std::int64_t effect_event = -1;  // index of its edge in the effect events; -1: missed

  core::Duration true_latency() const { return effect_time - cause_time; }
  friend bool operator==(const PassTruth&, const PassTruth&) = default;
};

// A pass seen on both sides: the pair a perfect matcher would produce.
struct TruePair {
  std::int64_t pass = 0;               // PassTruth::index
  std::int64_t cause_index = 0;        // index in the cause events
  std::int64_t effect_index = 0;       // index in the effect events
  core::Duration true_latency{0};      // effect true time - cause true time
  core::Duration measured_latency{0};  // effect timestamp - cause timestamp (what the rig reports)

  friend bool operator==(const TruePair&, const TruePair&) = default;
};

// One manoeuvre and the delays its command met on the way to the vehicle's wheel.
struct ManoeuvreTruth {
  std::int64_t index = 0;
  core::TimePoint start;         // the operator starts turning (Clock::simulated)
  double start_angle_deg = 0;    // wheel angle at rest before; 0 = the magnet group centred on the sensor
  double turn_deg = 0;           // signed angle of the first sweep (positive: increasing angle)
  bool returns = false;          // across and back: a second sweep of the opposite sign
  double return_deg = 0;         // signed angle of the return sweep (0 if none)
  core::Duration hold{0};        // pause between the sweeps (0 if none)
  core::TimePoint return_start;  // the operator starts the return sweep (if returns)
  double operator_speed_deg_s = 0;
  double vehicle_speed_deg_s = 0;
  bool vehicle_moving = false;           // the vehicle was driving (smaller actuator lag)
  core::Duration command_delay{0};       // motion start -> command on the wire (sampling wait + processing)
  core::Duration network_delay{0};       // on the wire -> received, including lost_packets command periods
  std::int32_t lost_packets = 0;         // command packets lost before one got through
  core::Duration stall_wait{0};          // of network_delay: sent -> released by a stalled link's queue
  core::Duration return_stall_wait{0};   // the same for the return sweep's first command (if returns)
  core::Duration execution_delay{0};     // received -> actuator set point (control-loop wait + processing)
  core::Duration actuator_lag{0};        // set point -> the vehicle's wheel starts to move
  core::Duration queue_delay{0};         // extra wait because the vehicle's previous sweep had not ended
  core::TimePoint vehicle_start;         // the vehicle's wheel starts to move (Clock::simulated)
  core::TimePoint vehicle_return_start;  // the vehicle's wheel starts the return sweep (if returns)

  // start -> vehicle_start: the motion-to-motion delay before any speed difference.
  core::Duration total_delay() const { return vehicle_start - start; }
  friend bool operator==(const ManoeuvreTruth&, const ManoeuvreTruth&) = default;
};

// One node's clock at one moment, as the model knows it and as its sync daemon would report it.
struct ClockSample {
  core::Role node = core::Role::cause;
  core::TimePoint true_time;           // Clock::simulated
  core::Duration error{0};             // clock reading - true time
  core::Duration estimated_offset{0};  // the daemon's last measured offset to its reference
  core::Duration error_bound{0};       // the daemon's maximum error; Duration::max() if unsynchronised
  core::Duration error_estimate{0};    // the daemon's standard uncertainty of its offset (ClockState)
  core::Duration rms_offset{0};        // RMS of its measured offsets
  double skew_ppm = 0;                 // sd of its slew rate, ppm
  // Nonzero: not a state but the record of a clock step of this size (new - old reading) at
  // true_time; `error` is then the error just after it.
  core::Duration step{0};

  friend bool operator==(const ClockSample&, const ClockSample&) = default;
};

}  // namespace m2mlat::sim
