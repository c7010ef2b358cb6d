// The hand's and the actuator's rotations: see gyro_motion.hpp.
#include "m2mlat/sim/gyro_motion.hpp"

#include <cmath>  // fabs, sqrt, llround: exact
#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/core/portable_math.hpp"

namespace m2mlat::sim {

namespace {
constexpr double kMinJerkPeak = 1.875;         // peak rate of a minimum-jerk rotation, in A/T
constexpr double kMinJerkAccel = 5.773502692;  // its peak acceleration, in A/T^2 (10/sqrt(3))
constexpr double kCosinePeak = 2.0;            // peak rate of a raised-cosine rotation, in A/T
constexpr double kCosineAccel = 6.283185307;   // its peak acceleration, in A/T^2 (2 pi)
constexpr double kTwoPi = 6.283185307179586;
}  // namespace

double rate_deg_s(const RateMotion& m, std::int64_t t_ns) {
  if (t_ns < m.onset_ns || t_ns >= m.end_ns()) return 0;
  const double tau = static_cast<double>(t_ns - m.onset_ns) * 1e-9;  // s into the motion
  const double T = static_cast<double>(m.duration_ns) * 1e-9;
  const double sign = m.amplitude_deg < 0 ? -1.0 : 1.0;
  if (m.shape == RateMotion::Shape::minimum_jerk) {
    const double s = tau / T;
    const double q = s * (1 - s);
    return m.amplitude_deg / T * 30 * q * q;
  }
  if (m.shape == RateMotion::Shape::raised_cosine)
    return m.amplitude_deg / T * (1 - core::portable_cos(kTwoPi * tau / T));
  const double ramp = m.peak_deg_s / m.accel_deg_s2;  // s accelerating (and decelerating)
  if (tau < ramp) return sign * m.accel_deg_s2 * tau;
  if (tau > T - ramp) return sign * m.accel_deg_s2 * (T - tau);
  return sign * m.peak_deg_s;
}

RateMotion hand_motion(std::int64_t onset_ns, double peak_deg_s, std::int64_t duration_ns, int direction,
                       RateMotion::Shape shape) {
  if (!(peak_deg_s > 0) || duration_ns <= 0)
    throw core::Error(core::ErrorKind::usage, "hand motion: the peak rate and the duration must be positive");
  if (shape == RateMotion::Shape::trapezoid)
    throw core::Error(core::ErrorKind::usage, "hand motion: a hand is minimum-jerk or raised-cosine");
  const double peak_in_a_over_t = shape == RateMotion::Shape::minimum_jerk ? kMinJerkPeak : kCosinePeak;
  RateMotion m;
  m.shape = shape;
  m.onset_ns = onset_ns;
  m.duration_ns = duration_ns;
  m.amplitude_deg =
      (direction < 0 ? -1.0 : 1.0) * peak_deg_s * (static_cast<double>(duration_ns) * 1e-9) / peak_in_a_over_t;
  m.peak_deg_s = peak_deg_s;
  return m;
}

RateMotion::Shape parse_hand_shape(std::string_view name) {
  if (name == "minimum-jerk") return RateMotion::Shape::minimum_jerk;
  if (name == "raised-cosine") return RateMotion::Shape::raised_cosine;
  throw core::Error(core::ErrorKind::usage,
                    "unknown hand shape '" + std::string(name) + "': minimum-jerk or raised-cosine");
}

std::string_view hand_shape_name(RateMotion::Shape shape) {
  return shape == RateMotion::Shape::raised_cosine ? "raised-cosine"
         : shape == RateMotion::Shape::trapezoid   ? "trapezoid"
                                                   : "minimum-jerk";
}

RateMotion actuator_motion(const RateMotion& command, std::int64_t delay_ns, const ActuatorLimits& limits) {
  if (!(limits.max_rate_deg_s > 0) || !(limits.max_accel_deg_s2 > 0) || delay_ns < 0)
    throw core::Error(core::ErrorKind::usage,
                      "actuator motion: limits must be positive and the delay not negative");
  RateMotion m = command;
  m.onset_ns = command.onset_ns + delay_ns;
  const double T = static_cast<double>(command.duration_ns) * 1e-9;
  const double angle = std::fabs(command.amplitude_deg);
  const double accel = command.shape == RateMotion::Shape::minimum_jerk    ? kMinJerkAccel * angle / (T * T)
                       : command.shape == RateMotion::Shape::raised_cosine ? kCosineAccel * angle / (T * T)
                                                                           : command.accel_deg_s2;
  if (command.peak_deg_s <= limits.max_rate_deg_s && accel <= limits.max_accel_deg_s2) return m;
  // At the limits: accelerate to the rate limit, or to the peak the angle allows.
  m.shape = RateMotion::Shape::trapezoid;
  m.accel_deg_s2 = limits.max_accel_deg_s2;
  const double full =
      limits.max_rate_deg_s * limits.max_rate_deg_s / limits.max_accel_deg_s2;  // angle of ramps
  double duration_s = 0;
  if (angle >= full) {
    m.peak_deg_s = limits.max_rate_deg_s;
    duration_s = 2 * limits.max_rate_deg_s / limits.max_accel_deg_s2 + (angle - full) / limits.max_rate_deg_s;
  } else {
    m.peak_deg_s = std::sqrt(angle * limits.max_accel_deg_s2);
    duration_s = 2 * m.peak_deg_s / limits.max_accel_deg_s2;
  }
  m.duration_ns = std::llround(duration_s * 1e9);
  return m;
}

}  // namespace m2mlat::sim
