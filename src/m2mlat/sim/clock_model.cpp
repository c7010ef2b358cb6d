// The disciplined clock pair: see clock_model.hpp for the model.
#include "m2mlat/sim/clock_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>  // sqrt (correctly rounded) and llround (exact)
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly

namespace m2mlat::sim {

using namespace std::chrono_literals;

namespace {
constexpr std::array<std::string_view, 4> kModeNames{"perfect", "co_referenced", "autonomous", "free"};

constexpr std::array<SyncInfo, 4> kSyncProfiles{{
    {"co_referenced", "the operator board serves time to the vehicle board: tight, with rare spikes"},
    {"autonomous", "each board follows its own time servers: larger wander, no shared reference"},
    {"perfect", "both clocks read true time exactly (isolates the latency model)"},
    {"free", "no synchronisation: each clock drifts from its initial offset at its drift rate"},
}};

// Clock stream numbers (the generator uses others for its concerns).
constexpr std::uint64_t kCauseClockStream = 0x636c6f636b2d6361;   // "clock-ca"
constexpr std::uint64_t kEffectClockStream = 0x636c6f636b2d6566;  // "clock-ef"

constexpr double kPrecisionNs = 1000;        // clock reading precision assumed by the bound, ns
constexpr double kMaxSkewRate = 15e-6;       // chrony's assumed worst frequency error between polls
constexpr double kDispersionAverage = 0.05;  // weight of a new measurement in the jitter estimate
constexpr double kLoopAverage = 0.02;        // weight of a new correction in the loop's error estimate

[[noreturn]] void fail(std::string_view field, std::string_view what) {
  throw core::Error(core::ErrorKind::usage, fmt::format("simulator setting '{}': {}", field, what));
}
}  // namespace

std::string_view to_string(SyncMode mode) { return kModeNames.at(static_cast<std::size_t>(mode)); }

SyncMode parse_sync_mode(std::string_view text) {
  for (std::size_t i = 0; i < kModeNames.size(); ++i)
    if (kModeNames[i] == text) return static_cast<SyncMode>(i);
  throw core::Error(
      core::ErrorKind::usage,
      fmt::format("unknown sync mode '{}' (expected perfect, co_referenced, autonomous or free)", text));
}

std::span<const SyncInfo> sync_profiles() { return kSyncProfiles; }

SyncConfig sync_profile(std::string_view name) {
  SyncConfig sync;
  sync.mode = parse_sync_mode(name);
  // A board to public or campus time servers: a few hundred microseconds of noise per measurement.
  sync.upstream = SyncLink{500us, 30ms, 0, 0ms};
  // The vehicle to the operator board over the teleoperation network: less noise (one hop, frequent
  // polls), but now and then a sync packet waits behind a burst and the clock is pulled ahead.
  sync.peer = SyncLink{150us, 10ms, 0.02, 4ms};
  return sync;
}

void validate(const ClockConfig& clock, std::string_view field) {
  auto key = [&](std::string_view part) { return fmt::format("{}.{}", field, part); };
  if (!(std::abs(clock.drift_ppm) <= 500)) fail(key("drift_ppm"), "must be within +-500");
  if (!(clock.wander_ppm_per_sqrt_s >= 0 && clock.wander_ppm_per_sqrt_s <= 1))
    fail(key("wander_ppm_per_sqrt_s"), "must be in [0, 1]");
  if (clock.initial_offset > 24h || clock.initial_offset < -24h)
    fail(key("initial_offset"), "must be within a day");
  if (clock.sync_bias > 1s || clock.sync_bias < -1s) fail(key("sync_bias"), "must be within a second");
  if (clock.step > 24h || clock.step < -24h) fail(key("step"), "must be within a day");
  if (clock.step_at.count() < 0) fail(key("step_at"), "must not be negative");
}

void validate(const SyncConfig& sync, std::string_view field) {
  auto key = [&](std::string_view part) { return fmt::format("{}.{}", field, part); };
  if (sync.poll_interval < 1ms || sync.poll_interval > 1h)
    fail(key("poll_interval"), "must be between 1ms and 1h");
  for (const auto& entry : {std::pair{&sync.upstream, "upstream"}, std::pair{&sync.peer, "peer"}}) {
    const SyncLink* link = entry.first;
    const char* name = entry.second;
    auto link_key = [&](std::string_view part) { return fmt::format("{}.{}.{}", field, name, part); };
    if (link->noise.count() < 0) fail(link_key("noise"), "must not be negative");
    if (link->rtt.count() < 0) fail(link_key("rtt"), "must not be negative");
    if (!(link->outlier_probability >= 0 && link->outlier_probability <= 1))
      fail(link_key("outlier_probability"), "must be in [0, 1]");
    if (link->outlier_mean > 1s || link->outlier_mean < -1s)
      fail(link_key("outlier_mean"), "must be within a second");
  }
  // Outside these the loop oscillates or diverges.
  if (!(sync.loop_gain > 0 && sync.loop_gain <= 1)) fail(key("loop_gain"), "must be in (0, 1]");
  if (!(sync.frequency_gain >= 0 && sync.frequency_gain <= 0.25))
    fail(key("frequency_gain"), "must be in [0, 0.25]");
  // Below 1 ppm the loop cannot follow a typical oscillator; chrony's own default is 83333 ppm.
  if (!(sync.max_slew_ppm >= 1 && sync.max_slew_ppm <= 100000))
    fail(key("max_slew_ppm"), "must be in [1, 100000]");
}

namespace {

// var(e) / var(a) of the daemon's loop in its steady state, unlimited: a = g m is the offset it
// slews away a poll, m = e + w the measured offset (w white: noise and outliers), and the frequency
// correction takes f m a poll, so with x the frequency error x poll interval
//   e' = (1 - f - g) e + x - (f + g) w,   x' = x - f e - f w.
// The stationary covariance P = A P A^T + B B^T (var(w) = 1), found by iterating; var(a) = g^2
// (var(e) + 1). With f = 0 it is 1 / (2 g); g 0.3, f 0.02 give 2.03. Plain double arithmetic in a
// fixed order: bit-identical on every platform.
double loop_variance_factor(double g, double f) {
  double pee = 0, pex = 0, pxx = 0;
  const double a11 = 1 - f - g, a21 = -f, b1 = -(f + g), b2 = -f;
  for (int i = 0; i < 4000; ++i) {
    const double ee = a11 * a11 * pee + 2 * a11 * pex + pxx + b1 * b1;
    const double ex = a11 * a21 * pee + (a11 + a21) * pex + pxx + b1 * b2;
    const double xx = a21 * a21 * pee + 2 * a21 * pex + pxx + b2 * b2;
    pee = ee, pex = ex, pxx = xx;
  }
  return pee / (g * g * (pee + 1));
}

}  // namespace

ClockPair::ClockPair(const ClockConfig& cause, const ClockConfig& effect, const SyncConfig& sync,
                     std::int64_t start_ns, std::uint64_t seed)
    : sync_(sync),
      cause_(cause, seed, kCauseClockStream),
      effect_(effect, seed, kEffectClockStream),
      grid_ns_(start_ns),
      wander_scale_(std::sqrt(static_cast<double>(sync.poll_interval.count()) * 1e-9) * 1e-6),
      loop_factor_(loop_variance_factor(sync.loop_gain, sync.frequency_gain)) {
  for (Node* node : {&cause_, &effect_}) node->step_true_ns = start_ns + node->config.step_at.count();
  if (sync_.mode == SyncMode::perfect) return;
  if (sync_.mode != SyncMode::free) {
    cause_.disciplined = effect_.disciplined = true;
    cause_.link = sync_.upstream;
    effect_.link = sync_.mode == SyncMode::co_referenced ? sync_.peer : sync_.upstream;
  }
  for (Node* node : {&cause_, &effect_}) {
    node->oscillator = node->config.drift_ppm * 1e-6;
    if (!node->disciplined) {
      node->error_ns = static_cast<double>(node->config.initial_offset.count());
      node->rate = node->oscillator;
    } else {
      // Converged before the run starts: at the bias from its reference, the drift already learnt.
      node->correction = node->oscillator;
      const auto noise = static_cast<double>(node->link.noise.count());
      node->dispersion_var = noise * noise;
      // var(a) = g^2 (var(e) + var(w)) and var(e) = loop_factor_ var(a): the loop's steady state
      // for the noise alone (outliers enter as they come).
      const double g2 = sync_.loop_gain * sync_.loop_gain;
      node->applied_var = g2 * noise * noise / (1 - g2 * loop_factor_);
      node->error_var = loop_factor_ * node->applied_var;
      node->error_ns = static_cast<double>(node->config.sync_bias.count());
    }
  }
  if (sync_.mode == SyncMode::co_referenced) effect_.error_ns += cause_.error_ns;
}

void ClockPair::discipline(Node& node, double reference_error_ns) {
  const SyncLink& link = node.link;
  const double noise = static_cast<double>(link.noise.count()) * node.rng.normal();
  const bool outlier = link.outlier_probability > 0 && node.rng.bernoulli(link.outlier_probability);
  const double outlier_size =
      outlier ? static_cast<double>(link.outlier_mean.count()) * node.rng.exponential() : 0.0;
  // The daemon sees the offset to its reference, shifted by the path's asymmetry; an outlier makes
  // the clock look behind by `outlier_size`, so the loop pulls it ahead.
  // After a step the daemon's reference moved with the clock: the step is part of the bias.
  const double bias =
      static_cast<double>(node.config.sync_bias.count() + (node.stepped ? node.config.step.count() : 0));
  const double measured = node.error_ns - reference_error_ns - bias + noise - outlier_size;
  node.measured_ns = measured;
  node.dispersion_var += kDispersionAverage * (measured * measured - node.dispersion_var);
  const auto interval = static_cast<double>(sync_.poll_interval.count());
  // The daemon's corrections (frequency and offset together) are limited to max_slew_ppm, as
  // chrony's maxslewrate limits them: a large measured offset is then slewed away over several polls.
  // While the limit holds the rate back the frequency correction stays as it was (a daemon knows the
  // offset left is its own slew's doing, not a frequency error): integrating it would wind the
  // correction up by frequency_gain x offset every poll of a long slew, and the clock would overshoot
  // by far more than the offset. min/max of doubles are exact: the run stays bit-identical everywhere.
  const double limit = sync_.max_slew_ppm * 1e-6;
  const double correction = node.correction + sync_.frequency_gain * measured / interval;
  const double wanted = -correction - sync_.loop_gain * measured / interval;
  // The daemon's estimate of its clock error's variance (state_of): from the offset a it slews
  // away in this interval beyond its frequency correction, ns. Unlimited, the loop turns var(a)
  // into loop_factor_ x var(a) on the clock. Held back by the limit, a is what the clock moved (an
  // outlier moves it by at most max_slew_ppm x the interval, not g x its full size) and the
  // frequency correction is left alone. The clock then returns as a proportional loop's does: off
  // by a, (1 - g) a, (1 - g)^2 a, ..., a^2 / (g (2 - g)) in squares over the polls, of which the
  // returning polls' own corrections (g (1 - g)^n a, counted as ordinary ones) give a^2 / (2 (2 - g))
  // without a frequency term; a^2 / (2 g) is the rest (exact for f = 0, within 4 % for f = 0.02).
  double applied = sync_.loop_gain * measured;
  double error_var = loop_factor_ * applied * applied;
  if (wanted >= -limit && wanted <= limit) {
    node.correction = correction;
    node.rate = node.oscillator + wanted;
  } else {
    const double rate = std::clamp(-node.correction - sync_.loop_gain * measured / interval, -limit, limit);
    node.rate = node.oscillator + rate;
    applied = -(rate + node.correction) * interval;
    error_var = applied * applied / (2 * sync_.loop_gain);
  }
  node.applied_var += kLoopAverage * (applied * applied - node.applied_var);
  node.error_var += kLoopAverage * (error_var - node.error_var);
}

void ClockPair::step() {
  const auto interval = static_cast<double>(sync_.poll_interval.count());
  for (Node* node : {&cause_, &effect_}) {
    node->error_ns += node->rate * interval;
    if (node->config.wander_ppm_per_sqrt_s > 0)
      node->oscillator += node->config.wander_ppm_per_sqrt_s * wander_scale_ * node->rng.normal();
    if (!node->disciplined) node->rate = node->oscillator;
  }
  grid_ns_ += sync_.poll_interval.count();
  for (Node* node : {&cause_, &effect_}) {
    if (node->config.step.count() != 0 && !node->stepped && node->step_true_ns <= grid_ns_) {
      node->error_ns += static_cast<double>(node->config.step.count());
      node->stepped = true;
    }
  }
  if (cause_.disciplined) discipline(cause_, 0.0);
  if (effect_.disciplined) discipline(effect_, sync_.mode == SyncMode::co_referenced ? cause_.error_ns : 0.0);
}

ClockState ClockPair::state_of(const Node& node, std::int64_t true_ns) const {
  ClockState state;
  const auto since_grid = static_cast<double>(true_ns - grid_ns_);
  state.error_ns = node.error_ns + node.rate * since_grid + step_part(node, true_ns);
  if (!node.disciplined) {
    state.error_bound = core::Duration::max();
    return state;
  }
  state.estimated_offset = core::Duration{std::llround(node.measured_ns)};
  // chrony's maximum error: half the root delay plus the root dispersion (measurement jitter,
  // precision, and the worst drift since the last measurement). In co_referenced mode the vehicle's
  // root includes the operator's, as a stratum-2 client's does.
  auto bound = [&](const Node& n) {
    return static_cast<double>(n.link.rtt.count()) / 2 + 3 * std::sqrt(n.dispersion_var) + kPrecisionNs +
           kMaxSkewRate * since_grid;
  };
  double total = bound(node);
  if (&node == &effect_ && sync_.mode == SyncMode::co_referenced) total += bound(cause_);
  state.error_bound = core::Duration{std::llround(total)};
  // The standard uncertainty the loop leaves on the clock, from the corrections it made (discipline).
  const double rms = std::sqrt(node.dispersion_var);
  state.rms_offset = core::Duration{std::llround(rms)};
  state.error_estimate = core::Duration{std::llround(std::sqrt(node.error_var))};
  // How fast it moves the clock (ppm): the RMS of its offset corrections per poll interval.
  state.skew_ppm = std::sqrt(node.applied_var) / static_cast<double>(sync_.poll_interval.count()) * 1e6;
  return state;
}

double ClockPair::step_part(const Node& node, std::int64_t true_ns) const {
  return node.config.step.count() != 0 && !node.stepped && node.step_true_ns <= true_ns
             ? static_cast<double>(node.config.step.count())
             : 0.0;
}

ClockState ClockPair::at(core::Role role, std::int64_t true_ns) {
  if (true_ns < grid_ns_)
    throw core::Error(core::ErrorKind::internal, "clock model queried at an earlier time than before");
  if (sync_.mode == SyncMode::perfect)
    return ClockState{step_part(role == core::Role::effect ? effect_ : cause_, true_ns), core::Duration{0},
                      core::Duration{0}};
  const std::int64_t interval = sync_.poll_interval.count();
  while (true_ns - grid_ns_ >= interval) step();
  return state_of(role == core::Role::effect ? effect_ : cause_, true_ns);
}

core::Duration ClockPair::error(core::Role role, std::int64_t true_ns) {
  return core::Duration{std::llround(at(role, true_ns).error_ns)};
}

}  // namespace m2mlat::sim
