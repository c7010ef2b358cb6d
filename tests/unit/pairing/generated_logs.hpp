// Generated edge logs with known true pairs, for the matcher's tests: the situations a teleoperation
// study meets (network stalls that queue commands, lost, bouncing and spurious edges, clock steps,
// wheels with several magnets), each switchable, independent of the simulator so that the matcher is
// not only tested against the model it was tuned on.
//
// A manoeuvre turns the operator's wheel across the magnets at a random speed; each magnet passing the
// sensor is one cause edge. The command for each pass reaches the vehicle after a network delay (held
// back while the link stalls, then released in order as the queue drains); the vehicle's wheel follows
// after an actuator lag, at a fraction of the operator's speed, each pass at least `min_effect_gap`
// after the previous one. All times are int64 ns.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace m2mlat::pairing::generated {

struct LogOptions {
  std::uint64_t seed = 1;
  int manoeuvres = 300;
  std::vector<double> magnets_deg = {0};  // magnet angles on both wheels
  double interval_min_s = 1.5, interval_max_s = 4.0;  // start-to-start of manoeuvres
  double pause_min_s = 0.2;                           // the wheel rests at least this long
  double speed_min_deg_s = 150, speed_max_deg_s = 400;
  double ratio_min = 0.6, ratio_max = 0.95;  // vehicle wheel speed / operator wheel speed
  double lag_s = 0.77, lag_sd_s = 0.072;     // actuator lag per manoeuvre (normal)
  double outlier_probability = 0.02;         // a manoeuvre's lag is longer by U(0.2, 0.6) s
  double net_s = 0.02, net_jitter_s = 0.01;  // network delay: base + exponential
  double stalls_per_minute = 0;              // link stalls (Poisson) ...
  double stall_min_s = 1, stall_max_s = 6;   // ... of a duration uniform in [min, max)
  double drain_s = 0.002;                    // queued commands leave this far apart after a stall
  double min_effect_gap_s = 0.03;            // the vehicle's wheel passes magnets at least this far apart
  double cause_loss = 0, effect_loss = 0;          // chance a pass gives no edge, per side
  double cause_spurious = 0, effect_spurious = 0;  // spurious edges per side, as a share of its passes
  double bounce_probability = 0;                   // chance an edge has 1-3 extra edges within 3 ms
  double effect_step_s = 0;                        // the vehicle's clock steps by this much ...
  double step_at = 0.5;                            // ... at this fraction of the run
};

struct Log {
  std::vector<std::int64_t> cause, effect;           // sorted edge times, ns
  std::set<std::pair<std::int64_t, std::int64_t>> truth;  // (cause index, effect index) of true pairs
  int max_edges_between = 0;  // most cause edges between a pass's cause and its effect edge
};

inline Log generate(const LogOptions& o) {
  std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ull + 7);
  const auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  const auto chance = [&](double p) { return p > 0 && uniform(0, 1) < p; };
  const auto ns = [](double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); };
  std::vector<double> angles = o.magnets_deg;
  std::sort(angles.begin(), angles.end());
  const double span = angles.back() - angles.front();

  // Passes: true cause and effect times (s from the start).
  struct Pass {
    double cause, effect;
  };
  std::vector<Pass> passes;
  double start = 1.0, last_end = 0;
  std::vector<std::pair<double, double>> stalls;  // [from, to)
  for (int m = 0; m < o.manoeuvres; ++m) {
    const double speed = uniform(o.speed_min_deg_s, o.speed_max_deg_s);
    const double ratio = uniform(o.ratio_min, o.ratio_max);
    double lag = std::normal_distribution<double>(o.lag_s, o.lag_sd_s)(rng);
    lag = std::max(lag, 0.35);
    if (chance(o.outlier_probability)) lag += uniform(0.2, 0.6);
    const bool reverse = (m % 2) == 1;  // the wheel sweeps back the other way next time
    for (std::size_t k = 0; k < angles.size(); ++k) {
      const double angle = reverse ? angles.back() - angles[angles.size() - 1 - k] : angles[k] - angles.front();
      const double offset = angle / speed;
      passes.push_back({start + offset, offset * (1.0 / ratio - 1.0) + lag});  // effect: lag part, for now
    }
    last_end = start + span / speed;
    start = std::max(start + uniform(o.interval_min_s, o.interval_max_s), last_end + o.pause_min_s);
  }
  const double run_end = start + 10;
  if (o.stalls_per_minute > 0) {
    double t = 5;
    while (true) {
      t += std::exponential_distribution<double>(o.stalls_per_minute / 60.0)(rng);
      if (t >= run_end) break;
      const double d = uniform(o.stall_min_s, o.stall_max_s);
      stalls.emplace_back(t, t + d);
      t += d;
    }
  }
  // Network: each pass's command arrives after the delay, or when the stall it falls into ends.
  double previous_arrival = 0, previous_effect = 0;
  std::size_t stall = 0;
  for (auto& p : passes) {
    double arrival = p.cause + o.net_s + std::exponential_distribution<double>(1.0 / o.net_jitter_s)(rng);
    while (stall < stalls.size() && stalls[stall].second <= arrival - 1e-9 && stalls[stall].second < p.cause)
      ++stall;
    for (std::size_t s = stall; s < stalls.size() && stalls[s].first <= arrival; ++s)
      if (arrival < stalls[s].second) arrival = stalls[s].second;
    arrival = std::max(arrival, previous_arrival + o.drain_s);  // in order
    previous_arrival = arrival;
    p.effect = std::max(arrival + p.effect, previous_effect + o.min_effect_gap_s);
    previous_effect = p.effect;
  }

  // Edges with labels: pass index, or -1 for spurious and bounce edges.
  struct Edge {
    std::int64_t t;
    std::int64_t pass;
  };
  std::vector<Edge> cause, effect;
  const double step_time = passes.empty() ? 0 : passes[static_cast<std::size_t>(
                                                    static_cast<double>(passes.size() - 1) * o.step_at)].effect;
  for (std::size_t i = 0; i < passes.size(); ++i) {
    const auto pi = static_cast<std::int64_t>(i);
    if (!chance(o.cause_loss)) cause.push_back({ns(passes[i].cause), pi});
    if (!chance(o.effect_loss)) {
      double t = passes[i].effect;
      if (o.effect_step_s != 0 && t >= step_time) t += o.effect_step_s;
      effect.push_back({ns(t), pi});
    }
  }
  const auto add_noise = [&](std::vector<Edge>& side, double spurious_share) {
    const auto real = side.size();
    const auto spurious = static_cast<std::size_t>(std::llround(spurious_share * static_cast<double>(passes.size())));
    for (std::size_t k = 0; k < spurious; ++k) side.push_back({ns(uniform(0.5, run_end)), -1});
    for (std::size_t k = 0; k < real; ++k)
      if (chance(o.bounce_probability)) {
        std::int64_t t = side[k].t;
        const int extra = 1 + static_cast<int>(uniform(0, 3));
        for (int b = 0; b < extra; ++b) {
          t += ns(uniform(0.00005, 0.001));
          side.push_back({t, -1});
        }
      }
    std::stable_sort(side.begin(), side.end(), [](const Edge& a, const Edge& b) { return a.t < b.t; });
  };
  add_noise(cause, o.cause_spurious);
  add_noise(effect, o.effect_spurious);

  Log log;
  std::vector<std::int64_t> cause_of(passes.size(), -1);
  for (std::size_t i = 0; i < cause.size(); ++i) {
    log.cause.push_back(cause[i].t);
    if (cause[i].pass >= 0) cause_of[static_cast<std::size_t>(cause[i].pass)] = static_cast<std::int64_t>(i);
  }
  for (std::size_t j = 0; j < effect.size(); ++j) {
    log.effect.push_back(effect[j].t);
    if (effect[j].pass < 0) continue;
    const auto c = cause_of[static_cast<std::size_t>(effect[j].pass)];
    if (c < 0) continue;
    log.truth.emplace(c, static_cast<std::int64_t>(j));
    const auto between = std::upper_bound(log.cause.begin(), log.cause.end(), effect[j].t) -
                         log.cause.begin() - c - 1;
    log.max_edges_between = std::max(log.max_edges_between, static_cast<int>(between));
  }
  return log;
}

}  // namespace m2mlat::pairing::generated
