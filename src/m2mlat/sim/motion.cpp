// Planning manoeuvres and the vehicle's response: see motion.hpp.
#include "m2mlat/sim/motion.hpp"

#include <algorithm>
#include <cmath>  // llround: exact

#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly

namespace m2mlat::sim {

namespace {
// Stream numbers: fixed forever, or every seed's rig changes.
constexpr std::uint64_t kOperatorStream = 1;
constexpr std::uint64_t kStationStream = 2;
constexpr std::uint64_t kNetworkStream = 3;
constexpr std::uint64_t kVehicleStream = 4;
constexpr std::uint64_t kStallStream = 5;
constexpr std::int32_t kMaxLostPackets = 1000;

// Seconds (double) -> ns.
std::int64_t seconds_to_ns(double seconds) { return std::llround(seconds * 1e9); }

// The first tick of a clock ticking at origin + k * period (k any integer) that is > t (strictly
// after, `strict`) or >= t.
std::int64_t next_tick(std::int64_t origin, std::int64_t period, std::int64_t t, bool strict) {
  const std::int64_t since = t - origin;
  std::int64_t k = since / period;
  if (since % period != 0 && since < 0) --k;  // floor division
  std::int64_t tick = origin + k * period;
  if (tick < t || (strict && tick == t)) tick += period;
  return tick;
}

}  // namespace

MotionPlanner::MotionPlanner(const RigConfig& config)
    : config_(config),
      operator_rng_(config.seed, kOperatorStream),
      station_rng_(config.seed, kStationStream),
      network_rng_(config.seed, kNetworkStream),
      vehicle_rng_(config.seed, kVehicleStream),
      stall_rng_(config.seed, kStallStream),
      stall_start_ns_(config.start.ns()),
      stall_end_ns_(config.start.ns()) {
  const auto& magnets = config.magnets_deg;
  for (std::size_t i = 0; i < magnets.size(); ++i) ascending_.push_back(static_cast<std::int32_t>(i));
  std::sort(ascending_.begin(), ascending_.end(), [&](std::int32_t a, std::int32_t b) {
    return magnets[static_cast<std::size_t>(a)] < magnets[static_cast<std::size_t>(b)];
  });
  min_deg_ = magnets[static_cast<std::size_t>(ascending_.front())];
  max_deg_ = magnets[static_cast<std::size_t>(ascending_.back())];
  station_phase_ns_ = station_rng_.uniform_int(0, config.station.command_period.count() - 1);
  control_phase_ns_ = vehicle_rng_.uniform_int(0, config.vehicle.control_period.count() - 1);
  clearance_max_deg_ = clearance_max_deg(config.motion, max_deg_ - min_deg_);
  clearance_deg_ = operator_rng_.uniform(config.motion.clearance_min_deg, clearance_max_deg_);
  next_start_ns_ = config.start.ns() + uniform_ns(config.motion.interval_min, config.motion.interval_max);
}

std::int64_t MotionPlanner::uniform_ns(core::Duration lo, core::Duration hi) {
  if (hi <= lo) return lo.count();
  return operator_rng_.uniform_int(lo.count(), hi.count() - 1);
}

bool MotionPlanner::has_next() const {
  if (config_.manoeuvres > 0 && index_ >= config_.manoeuvres) return false;
  if (config_.duration.count() > 0 && next_start_ns_ - config_.start.ns() >= config_.duration.count())
    return false;
  return true;
}

MotionPlanner::Delays MotionPlanner::draw_delays(std::int64_t motion_start_ns) {
  Delays d;
  const std::int64_t origin = config_.start.ns();
  // Command generation: the station notices the motion at its next sampling tick, then builds and
  // sends the packet.
  const std::int64_t period = config_.station.command_period.count();
  const std::int64_t tick = next_tick(origin + station_phase_ns_, period, motion_start_ns, true);
  d.command = tick - motion_start_ns + sample(config_.station.processing, station_rng_).count();
  // Network: every lost packet costs a command period (the next packet carries the motion too).
  const auto& net = config_.network;
  while (d.lost < kMaxLostPackets && network_rng_.bernoulli(net.loss_probability)) ++d.lost;
  const std::int64_t base = sample(net.delay, network_rng_).count();
  const bool burst = network_rng_.bernoulli(net.burst_probability);
  const std::int64_t burst_ns = sample(net.burst, network_rng_).count();
  d.network = d.lost * period + base + (burst ? burst_ns : 0);
  d.base = base;
  d.unstalled = d.network;
  // A stall holds the packet (nothing is lost from the queue) until the link drains it.
  d.stall_wait = stall_wait(motion_start_ns + d.command);
  if (d.stall_wait > 0) {
    d.lost = 0;
    d.network = d.stall_wait + base;
  }
  // Execution: the vehicle's loop picks the command up at its next cycle.
  const std::int64_t arrival = motion_start_ns + d.command + d.network;
  const std::int64_t cycle =
      next_tick(origin + control_phase_ns_, config_.vehicle.control_period.count(), arrival, false);
  d.execution = cycle - arrival + sample(config_.vehicle.execution, vehicle_rng_).count();
  // Actuator dead time, longer when standing.
  d.moving = vehicle_rng_.bernoulli(config_.vehicle.moving_probability);
  const std::int64_t moving_lag = sample(config_.vehicle.actuator_lag_moving, vehicle_rng_).count();
  const std::int64_t static_lag = sample(config_.vehicle.actuator_lag_static, vehicle_rng_).count();
  d.actuator = d.moving ? moving_lag : static_lag;
  return d;
}

std::int64_t MotionPlanner::stall_wait(std::int64_t send_ns) {
  const auto& net = config_.network;
  if (net.stall_per_minute <= 0) return 0;
  const std::int64_t period = config_.station.command_period.count();
  const std::int64_t drain = net.stall_drain.count();
  // The queue is empty again once the drain has caught up with the station: the k-th packet sent
  // since the stall began leaves at end + k * drain, and is held while that is after start + k * period.
  auto drained_ns = [&] {
    const std::int64_t packets = (stall_end_ns_ - stall_start_ns_ + (period - drain) - 1) / (period - drain);
    return stall_start_ns_ + packets * period;
  };
  while (drained_ns() <= send_ns) {  // the next stall: an exponential gap after the link is clear
    stall_start_ns_ =
        drained_ns() +
        std::max<std::int64_t>(1, std::llround(60e9 / net.stall_per_minute * stall_rng_.exponential()));
    stall_end_ns_ = stall_start_ns_ + std::max<std::int64_t>(1, sample(net.stall, stall_rng_).count());
  }
  if (send_ns < stall_start_ns_) return 0;
  // The packets the station sent since the stall began leave the queue first, one per drain step.
  const std::int64_t ahead = (send_ns - stall_start_ns_) / period;
  return std::max<std::int64_t>(0, stall_end_ns_ + ahead * drain - send_ns);
}

std::int64_t MotionPlanner::add_sweep(ManoeuvrePlan& plan, std::int32_t sweep, int direction,
                                      double clearance_before_deg, double clearance_after_deg,
                                      std::int64_t cause_start_ns, std::int64_t effect_start_ns,
                                      double cause_speed, double effect_speed) const {
  const auto& magnets = config_.magnets_deg;
  const std::size_t n = ascending_.size();
  for (std::size_t k = 0; k < n; ++k) {
    // Increasing angle meets the largest magnet angle first; decreasing angle the smallest.
    const std::int32_t magnet = direction > 0 ? ascending_[n - 1 - k] : ascending_[k];
    const double phi = magnets[static_cast<std::size_t>(magnet)];
    const double offset_deg = clearance_before_deg + (direction > 0 ? max_deg_ - phi : phi - min_deg_);
    plan.passes.push_back({sweep, magnet, cause_start_ns + seconds_to_ns(offset_deg / cause_speed),
                           effect_start_ns + seconds_to_ns(offset_deg / effect_speed)});
  }
  const double angle = clearance_before_deg + (max_deg_ - min_deg_) + clearance_after_deg;
  return seconds_to_ns(angle / cause_speed);
}

void MotionPlanner::next(ManoeuvrePlan& plan) {
  const auto& m = config_.motion;
  const auto& v = config_.vehicle;
  plan.passes.clear();
  ManoeuvreTruth& t = plan.truth;
  t = ManoeuvreTruth{};
  t.index = index_++;
  const std::int64_t start = next_start_ns_;
  t.start = true_time(start);

  // The operator's choices, all drawn every time so that the stream never depends on outcomes.
  const double speed = operator_rng_.uniform(m.speed_min_deg_s, m.speed_max_deg_s);
  const double clearance_across = operator_rng_.uniform(m.clearance_min_deg, clearance_max_deg_);
  const double clearance_back = operator_rng_.uniform(m.clearance_min_deg, clearance_max_deg_);
  const bool returns = operator_rng_.bernoulli(m.return_probability);
  const std::int64_t hold = uniform_ns(m.hold_min, m.hold_max);
  const std::int64_t interval = uniform_ns(m.interval_min, m.interval_max);

  // The vehicle's response.
  const Delays d = draw_delays(start);
  const double ratio = vehicle_rng_.uniform(v.speed_ratio_min, v.speed_ratio_max);
  const double span = max_deg_ - min_deg_;
  const double angle0 = clearance_deg_ + span + clearance_across;
  const std::int64_t back_start = start + seconds_to_ns(angle0 / speed) + hold;  // if it returns
  // The return's first command meets the link as it is then: a stall may hold one sweep and not the other.
  const std::int64_t back_wait = returns ? stall_wait(back_start + d.command) : 0;
  const std::int64_t back_network = back_wait > 0 ? back_wait + d.base : d.unstalled;
  // A sweep whose commands waited in a stall's queue reaches the vehicle as a burst: its set point
  // runs ahead of the wheel, and the actuator turns at its maximum speed.
  const bool held = d.stall_wait > 0 || back_wait > 0;
  const double vehicle_speed = held ? v.max_speed_deg_s : std::min(speed * ratio, v.max_speed_deg_s);
  const std::int64_t delay = d.command + d.network + d.execution + d.actuator;
  const std::int64_t back_delay = d.command + back_network + d.execution + d.actuator;

  const int direction = -side_;
  t.start_angle_deg = side_ < 0 ? -span / 2 - clearance_deg_ : span / 2 + clearance_deg_;
  t.turn_deg = direction * (clearance_deg_ + span + clearance_across);
  t.operator_speed_deg_s = speed;
  t.vehicle_speed_deg_s = vehicle_speed;
  t.vehicle_moving = d.moving;
  t.command_delay = core::Duration{d.command};
  t.network_delay = core::Duration{d.network};
  t.lost_packets = d.lost;
  t.stall_wait = core::Duration{d.stall_wait};
  t.return_stall_wait = core::Duration{back_wait};
  t.execution_delay = core::Duration{d.execution};
  t.actuator_lag = core::Duration{d.actuator};

  auto vehicle_sweep_start = [&](std::int64_t wanted) {
    return vehicle_busy_before_ ? std::max(wanted, vehicle_free_ns_ + v.min_pause.count()) : wanted;
  };
  const std::int64_t vehicle_start = vehicle_sweep_start(start + delay);
  t.queue_delay = core::Duration{vehicle_start - (start + delay)};
  t.vehicle_start = true_time(vehicle_start);
  const std::int64_t duration0 = add_sweep(plan, 0, direction, clearance_deg_, clearance_across, start,
                                           vehicle_start, speed, vehicle_speed);
  vehicle_free_ns_ = vehicle_start + seconds_to_ns(angle0 / vehicle_speed);
  vehicle_busy_before_ = true;
  std::int64_t operator_end = start + duration0;

  if (returns) {
    t.returns = true;
    t.hold = core::Duration{hold};
    t.return_deg = -direction * (clearance_across + span + clearance_back);
    const std::int64_t vehicle_back_start = vehicle_sweep_start(back_start + back_delay);
    t.return_start = true_time(back_start);
    t.vehicle_return_start = true_time(vehicle_back_start);
    const std::int64_t duration1 = add_sweep(plan, 1, -direction, clearance_across, clearance_back,
                                             back_start, vehicle_back_start, speed, vehicle_speed);
    const double angle1 = clearance_across + span + clearance_back;
    vehicle_free_ns_ = vehicle_back_start + seconds_to_ns(angle1 / vehicle_speed);
    operator_end = back_start + duration1;
    clearance_deg_ = clearance_back;  // back on the side it started from
  } else {
    side_ = -side_;
    clearance_deg_ = clearance_across;
  }
  next_start_ns_ = start + std::max(interval, operator_end - start + m.min_pause.count());
}

double wheel_angle_deg(const ManoeuvreTruth& m, core::Role role, core::TimePoint t) {
  const bool vehicle = role == core::Role::effect;
  const double speed = vehicle ? m.vehicle_speed_deg_s : m.operator_speed_deg_s;
  auto swept = [&](core::TimePoint from, double angle) {  // signed angle turned by t in a sweep from `from`
    const double seconds = static_cast<double>((t - from).count()) * 1e-9;
    const double turned = std::min(std::abs(angle), speed * seconds);
    return angle < 0 ? -turned : turned;
  };
  const core::TimePoint first = vehicle ? m.vehicle_start : m.start;
  if (t <= first) return m.start_angle_deg;
  const core::TimePoint second = vehicle ? m.vehicle_return_start : m.return_start;
  if (!m.returns || t <= second) return m.start_angle_deg + swept(first, m.turn_deg);
  return m.start_angle_deg + m.turn_deg + swept(second, m.return_deg);
}

}  // namespace m2mlat::sim
