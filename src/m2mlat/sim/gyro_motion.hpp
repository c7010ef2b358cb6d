// The rotations a simulated gyroscope sees, with their true onset and end: an operator's hand and a
// vehicle's steering actuator. Rates are deg/s about the steering axis; times int64 ns.
//
// The hand: a minimum-jerk rotation (Flash and Hogan, 1985: the smoothest point-to-point movement,
// the usual model of a human reaching or turning movement). Rate(s) = A/T * 30 s^2 (1 - s)^2 for
// s = (t - onset) / T in [0, 1]: it leaves rest with zero rate and zero acceleration (a hand cannot
// jump to speed), peaks at 1.875 A/T mid-way and returns to rest at onset + T. A second hand, the
// raised cosine Rate(s) = A/T (1 - cos 2 pi s), also leaves rest smoothly (rate ~ s^2 at first) but is no
// polynomial: it checks that a detector whose model is a polynomial start (onset/flank) does not owe
// its figures to the minimum-jerk curve being one.
// The actuator: the vehicle's wheel repeats the operator's rotation after a delay. A servo that can
// follow the command reproduces its shape; one that cannot (the command's peak rate or acceleration
// beyond the actuator's limits) turns the same angle at its limits: constant acceleration to the rate
// limit (or to the peak a short turn allows), then back to rest (a trapezoidal rate). The motor's
// torque rise (a current loop's millisecond) is not modelled: the acceleration steps.
#pragma once

#include <cstdint>
#include <string_view>

namespace m2mlat::sim {

struct RateMotion {
  enum class Shape : std::uint8_t { minimum_jerk, trapezoid, raised_cosine };
  Shape shape = Shape::minimum_jerk;
  std::int64_t onset_ns = 0;     // the true onset: the first instant of non-zero rate, ns
  std::int64_t duration_ns = 0;  // true end = onset + duration, ns
  double amplitude_deg = 0;      // signed angle turned, deg
  double accel_deg_s2 = 0;       // trapezoid: the constant acceleration, deg/s^2
  double peak_deg_s = 0;         // the largest |rate| of the motion, deg/s

  std::int64_t end_ns() const { return onset_ns + duration_ns; }
};

// The true rate of `m` at t (0 outside [onset, end)), deg/s, signed as the amplitude.
double rate_deg_s(const RateMotion& m, std::int64_t t_ns);

// A hand's rotation peaking at `peak_deg_s` (> 0) over `duration_ns` (> 0), turning the sign of
// `direction` (+1 or -1); `shape` minimum_jerk or raised_cosine.
RateMotion hand_motion(std::int64_t onset_ns, double peak_deg_s, std::int64_t duration_ns, int direction,
                       RateMotion::Shape shape = RateMotion::Shape::minimum_jerk);
// "minimum-jerk" | "raised-cosine"; throws core::Error(usage) for another name.
RateMotion::Shape parse_hand_shape(std::string_view name);
std::string_view hand_shape_name(RateMotion::Shape shape);

struct ActuatorLimits {
  double max_rate_deg_s = 360;     // the actuator's rate limit, deg/s
  double max_accel_deg_s2 = 1500;  // its acceleration limit, deg/s^2
};
// The vehicle's rotation answering `command` after `delay_ns`: the same shape when within `limits`,
// else a trapezoid at the limits turning the same angle.
RateMotion actuator_motion(const RateMotion& command, std::int64_t delay_ns, const ActuatorLimits& limits);

}  // namespace m2mlat::sim
