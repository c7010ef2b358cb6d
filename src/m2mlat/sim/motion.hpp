// The motion model: the operator's manoeuvres, the wheel geometry that turns them into magnet
// passes, and the chain of delays (command generation, network, execution, actuator) after which
// the vehicle's wheel repeats the motion. Produces true times only; sensors and clocks come later.
//
// Geometry: the wheel angle theta is 0 when the magnet group is centred on the sensor; magnet i
// (at phi_i on the wheel) is at the sensor when theta = c - phi_i, c the centre of the group. The
// wheel rests with every magnet on one side; a sweep turns it across at constant speed to rest
// `clearance` degrees past the last magnet on the other side, so each magnet passes exactly once,
// in the order of the sweep's direction.
#pragma once

#include <cstdint>
#include <vector>

#include "m2mlat/sim/random.hpp"
#include "m2mlat/sim/rig_config.hpp"
#include "m2mlat/sim/truth.hpp"

namespace m2mlat::sim {

// One magnet pass, both wheels, true times in ns since the epoch.
struct PlannedPass {
  std::int32_t sweep = 0;
  std::int32_t magnet = 0;
  std::int64_t cause_ns = 0;
  std::int64_t effect_ns = 0;
};

struct ManoeuvrePlan {
  ManoeuvreTruth truth;
  std::vector<PlannedPass> passes;  // in the operator's order (also the vehicle's)
};

// The angle (degrees, the wheel-angle convention above) of the operator's (cause) or the vehicle's
// (effect) wheel at true time `t` (Clock::simulated), from the manoeuvre's start until the next
// manoeuvre starts.
double wheel_angle_deg(const ManoeuvreTruth& manoeuvre, core::Role role, core::TimePoint t);

class MotionPlanner {
 public:
  explicit MotionPlanner(const RigConfig& config);  // config must be valid

  // True while another manoeuvre starts within the configured count / duration.
  bool has_next() const;
  // True start time (ns since the epoch) of the next manoeuvre; after the last one, the time the
  // next would have started.
  std::int64_t next_start_ns() const { return next_start_ns_; }
  // Plans the next manoeuvre (has_next() must be true) into `plan` (its vectors are reused).
  void next(ManoeuvrePlan& plan);

 private:
  struct Delays {
    std::int64_t command = 0, network = 0, execution = 0, actuator = 0;
    std::int64_t base = 0;        // the delivered packet's own one-way delay
    std::int64_t unstalled = 0;   // the network delay had no stall held the packet
    std::int64_t stall_wait = 0;  // send -> the stall's queue released the packet (0: no stall)
    std::int32_t lost = 0;
    bool moving = false;
  };
  Delays draw_delays(std::int64_t motion_start_ns);
  // If a command packet sent at `send_ns` falls in a stall: how long it waits in the queue (from
  // sending to leaving the drained queue, ns); else 0. Calls come with non-decreasing send times.
  std::int64_t stall_wait(std::int64_t send_ns);
  // Appends a sweep's passes; returns the sweep's duration on the operator's wheel (ns).
  std::int64_t add_sweep(ManoeuvrePlan& plan, std::int32_t sweep, int direction, double clearance_before_deg,
                         double clearance_after_deg, std::int64_t cause_start_ns,
                         std::int64_t effect_start_ns, double cause_speed, double effect_speed) const;
  std::int64_t uniform_ns(core::Duration lo, core::Duration hi);

  const RigConfig& config_;
  Rng operator_rng_;                 // the operator: intervals, speeds, clearances, returns, holds
  Rng station_rng_;                  // command processing and the station's tick phase
  Rng network_rng_;                  // delays, bursts, losses
  Rng vehicle_rng_;                  // control loop, actuator, speed ratio, moving or not
  Rng stall_rng_;                    // stalls of the link: when and how long
  std::int64_t stall_start_ns_ = 0;  // the current or next stall [start, end) (true ns)
  std::int64_t stall_end_ns_ = 0;
  std::vector<std::int32_t> ascending_;  // magnet indices by increasing angle
  double min_deg_ = 0, max_deg_ = 0;     // smallest and largest magnet angle
  std::int64_t station_phase_ns_ = 0;    // the station samples at start + phase + n * period
  std::int64_t control_phase_ns_ = 0;    // the vehicle's loop runs at start + phase + n * period
  std::int64_t index_ = 0;               // manoeuvres planned so far
  std::int64_t next_start_ns_ = 0;
  int side_ = -1;                     // -1: the wheel rests below every magnet's crossing angle; +1: above
  double clearance_deg_ = 0;          // how far past the outermost magnet it rests
  double clearance_max_deg_ = 0;      // the farthest it may rest (rig_config.hpp: clearance_max_deg)
  std::int64_t vehicle_free_ns_ = 0;  // the vehicle's previous sweep ends (true ns)
  bool vehicle_busy_before_ = false;  // a previous sweep exists
};

}  // namespace m2mlat::sim
