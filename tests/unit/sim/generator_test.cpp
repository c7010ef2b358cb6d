// The simulated rig's event streams: determinism, order, kernel-like sequence numbers, edge counts,
// imperfection rates, and the consistency of the ground truth with the events.
#include "m2mlat/sim/generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "sim_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;
using namespace std::chrono_literals;
using core::Role;

namespace {
constexpr Role kRoles[] = {Role::cause, Role::effect};

// Standard error of a binomial count, for "at about its configured rate" checks.
double binomial_sigma(double n, double p) { return std::sqrt(n * p * (1 - p)); }
}  // namespace

TEST(Generator, SameSeedSameRunDifferentSeedDifferentRun) {
  RigConfig config;
  config.manoeuvres = 300;
  config.magnets_deg = {0, 120, 240};
  config.motion.return_probability = 0.3;
  const Simulation a = simulate(config);
  const Simulation b = simulate(config);
  EXPECT_EQ(a.cause_events, b.cause_events);
  EXPECT_EQ(a.effect_events, b.effect_events);
  EXPECT_EQ(a.cause_truth, b.cause_truth);
  EXPECT_EQ(a.effect_truth, b.effect_truth);
  EXPECT_EQ(a.passes, b.passes);
  EXPECT_EQ(a.pairs, b.pairs);
  EXPECT_EQ(a.manoeuvres, b.manoeuvres);
  EXPECT_EQ(a.clock_samples, b.clock_samples);

  config.seed = 2;
  const Simulation c = simulate(config);
  EXPECT_NE(a.cause_events, c.cause_events);
  EXPECT_NE(a.effect_events, c.effect_events);
  EXPECT_NE(a.manoeuvres, c.manoeuvres);
}

// The run for seed 1 is pinned: the same bits from every compiler, library and CPU. If the model
// is changed on purpose, print the new values and update them here (and say so in the change).
TEST(Generator, OutputIsPinnedAcrossPlatforms) {
  RigConfig config;
  config.manoeuvres = 50;
  config.magnets_deg = {0, 20, 40};
  const Simulation run = simulate(config);
  std::uint64_t digest = 1469598103934665603ULL;  // FNV-1a over every timestamp and truth time
  auto mix = [&](std::int64_t v) {
    for (int i = 0; i < 8; ++i) {
      digest ^= static_cast<std::uint64_t>(v >> (8 * i)) & 0xff;
      digest *= 1099511628211ULL;
    }
  };
  for (Role role : kRoles) {
    for (const auto& e : run.events(role)) mix(e.time.ns());
    for (const auto& t : run.truth(role)) mix(t.true_time.ns());
  }
  for (const auto& s : run.clock_samples) mix(s.error.count());
  EXPECT_EQ(run.cause_events.size(), 156u);
  EXPECT_EQ(run.effect_events.size(), 163u);
  EXPECT_EQ(digest, 0xe3f539505a6d6775ULL) << std::hex << "digest 0x" << digest;
}

TEST(Generator, EventsAreInTimeOrderWithKernelSequenceNumbers) {
  RigConfig config;
  config.manoeuvres = 2000;
  config.magnets_deg = {0, 20, 40};
  config.motion.return_probability = 0.2;
  for (auto* sensor : {&config.cause_sensor, &config.effect_sensor}) {
    sensor->bounce_probability = 0.3;
    sensor->spurious_per_minute = 3;
  }
  const Simulation run = simulate(config);
  for (Role role : kRoles) {
    const auto& events = run.events(role);
    ASSERT_FALSE(events.empty());
    for (std::size_t i = 0; i < events.size(); ++i) {
      const auto& e = events[i];
      EXPECT_EQ(e.seqno, i + 1);
      EXPECT_EQ(e.line_seqno, i + 1);
      EXPECT_EQ(e.flags, core::kFlagSimulated);
      EXPECT_EQ(e.edge, core::Edge::falling);
      EXPECT_EQ(e.time.clock(), core::Clock::realtime);
      EXPECT_EQ(e.channel, "wheel");
      EXPECT_EQ(e.node, role == Role::cause ? "operator" : "vehicle");
      if (i > 0) {
        EXPECT_GT(e.time, events[i - 1].time) << "event " << i;
      }
    }
  }
  EXPECT_GE(run.cause_events.front().time.ns(), config.start.ns());
}

TEST(Generator, WithoutImperfectionsEveryPassGivesOneEdgePerSide) {
  for (const std::vector<double>& magnets : {std::vector<double>{0}, {0, 120, 240}, {0, 20, 40}}) {
    RigConfig config = test::ideal_config(400);
    config.magnets_deg = magnets;
    config.motion.return_probability = 0.25;
    const Simulation run = simulate(config);
    ASSERT_EQ(run.manoeuvres.size(), 400u);
    std::size_t sweeps = 0;
    for (const auto& m : run.manoeuvres) sweeps += m.returns ? 2 : 1;
    const std::size_t passes = sweeps * magnets.size();
    EXPECT_EQ(run.passes.size(), passes);
    EXPECT_EQ(run.cause_events.size(), passes);
    EXPECT_EQ(run.effect_events.size(), passes);
    EXPECT_EQ(run.pairs.size(), passes);
    for (std::size_t i = 0; i < run.passes.size(); ++i) {
      EXPECT_EQ(run.passes[i].index, static_cast<std::int64_t>(i));
      EXPECT_GE(run.passes[i].cause_event, 0);
      EXPECT_GE(run.passes[i].effect_event, 0);
    }
    // Each manoeuvre's sweep passes every magnet exactly once.
    std::map<std::pair<std::int64_t, int>, std::set<int>> magnets_per_sweep;
    for (const auto& p : run.passes) magnets_per_sweep[{p.manoeuvre, p.sweep}].insert(p.magnet);
    for (const auto& [key, seen] : magnets_per_sweep) EXPECT_EQ(seen.size(), magnets.size());
  }
}

TEST(Generator, WheelsAreAtTheMagnetAngleAtEachPass) {
  RigConfig config = test::ideal_config(300);
  config.magnets_deg = {10, 130, 250};
  config.motion.return_probability = 0.4;
  const Simulation run = simulate(config);
  const double centre = (10 + 250) / 2.0;  // the sensor faces the middle of the magnet group
  for (const PassTruth& pass : run.passes) {
    const ManoeuvreTruth& m = run.manoeuvres[static_cast<std::size_t>(pass.manoeuvre)];
    const double crossing = centre - config.magnets_deg[static_cast<std::size_t>(pass.magnet)];
    EXPECT_NEAR(wheel_angle_deg(m, Role::cause, pass.cause_time), crossing, 1e-3);
    EXPECT_NEAR(wheel_angle_deg(m, Role::effect, pass.effect_time), crossing, 1e-3);
  }
  // Both wheels end each manoeuvre where the next one starts: the vehicle repeats the motion.
  for (std::size_t i = 1; i < run.manoeuvres.size(); ++i) {
    const auto& before = run.manoeuvres[i - 1];
    const auto& after = run.manoeuvres[i];
    EXPECT_NEAR(wheel_angle_deg(before, Role::cause, after.start), after.start_angle_deg, 1e-9);
    EXPECT_NEAR(wheel_angle_deg(before, Role::effect, after.vehicle_start), after.start_angle_deg, 1e-9);
  }
}

TEST(Generator, DurationLimitsTheRun) {
  RigConfig config = test::ideal_config(0);
  config.duration = 10min;
  const Simulation run = simulate(config);
  ASSERT_FALSE(run.manoeuvres.empty());
  EXPECT_LT(run.manoeuvres.back().start.ns() - config.start.ns(), config.duration.count());
  // 1.5..4 s apart: between 150 and 400 manoeuvres in ten minutes.
  EXPECT_GT(run.manoeuvres.size(), 150u);
  EXPECT_LT(run.manoeuvres.size(), 400u);
}

TEST(Generator, ManoeuvresAreNotPeriodic) {
  const Simulation run = simulate(test::ideal_config(500));
  std::vector<double> gaps;
  for (std::size_t i = 1; i < run.manoeuvres.size(); ++i)
    gaps.push_back(static_cast<double>((run.manoeuvres[i].start - run.manoeuvres[i - 1].start).count()) /
                   1e9);
  EXPECT_GE(test::quantile(gaps, 0), 1.5);
  EXPECT_LE(test::quantile(gaps, 1), 4.0);
  EXPECT_GT(test::iqr(gaps), 0.9);  // uniform on 1.5..4 s: IQR 1.25 s
}

TEST(Generator, TruthAgreesWithEvents) {
  RigConfig config;
  config.manoeuvres = 1500;
  config.magnets_deg = {0, 120, 240};
  config.sync = sync_profile("autonomous");
  const Simulation run = simulate(config);
  for (Role role : kRoles) {
    const auto& events = run.events(role);
    const auto& truth = run.truth(role);
    ASSERT_EQ(events.size(), truth.size());
    for (std::size_t i = 0; i < events.size(); ++i) {
      const auto& t = truth[i];
      EXPECT_EQ(t.true_time.clock(), core::Clock::simulated);
      // The timestamp is the true edge, plus the interrupt latency, read on the node's clock.
      EXPECT_EQ(events[i].time.ns(), t.true_time.ns() + t.irq_latency.count() + t.clock_error.count());
      EXPECT_GE(t.irq_latency, 2us);
      if (t.kind == EdgeKind::spurious) {
        EXPECT_EQ(t.pass, -1);
        EXPECT_EQ(t.manoeuvre, -1);
      } else {
        ASSERT_GE(t.pass, 0);
        const PassTruth& pass = run.passes[static_cast<std::size_t>(t.pass)];
        EXPECT_EQ(pass.manoeuvre, t.manoeuvre);
        EXPECT_EQ(pass.magnet, t.magnet);
        const auto pass_time = role == Role::cause ? pass.cause_time : pass.effect_time;
        if (t.kind == EdgeKind::pass) {
          EXPECT_EQ(t.true_time, pass_time);
          EXPECT_EQ(role == Role::cause ? pass.cause_event : pass.effect_event, static_cast<std::int64_t>(i));
        } else {
          EXPECT_GT(t.true_time, pass_time);
          EXPECT_LE(t.true_time - pass_time, config.effect_sensor.bounce_window);
        }
      }
    }
  }
  ASSERT_GT(run.pairs.size(), 1000u);
  for (const TruePair& pair : run.pairs) {
    const auto& c = run.cause_truth[static_cast<std::size_t>(pair.cause_index)];
    const auto& e = run.effect_truth[static_cast<std::size_t>(pair.effect_index)];
    EXPECT_EQ(c.kind, EdgeKind::pass);
    EXPECT_EQ(e.kind, EdgeKind::pass);
    EXPECT_EQ(c.pass, pair.pass);
    EXPECT_EQ(e.pass, pair.pass);
    EXPECT_EQ(pair.true_latency, e.true_time - c.true_time);
    EXPECT_EQ(pair.true_latency, run.passes[static_cast<std::size_t>(pair.pass)].true_latency());
    const auto& ce = run.cause_events[static_cast<std::size_t>(pair.cause_index)];
    const auto& ee = run.effect_events[static_cast<std::size_t>(pair.effect_index)];
    EXPECT_EQ(pair.measured_latency, ee.time - ce.time);
    // measured - true = the clocks' disagreement plus the interrupt latencies' difference.
    EXPECT_EQ(pair.measured_latency - pair.true_latency,
              (e.clock_error + e.irq_latency) - (c.clock_error + c.irq_latency));
  }
  // Manoeuvre truth: the delay chain adds up, and the vehicle starts after it.
  for (const auto& m : run.manoeuvres) {
    EXPECT_EQ(m.total_delay(),
              m.command_delay + m.network_delay + m.execution_delay + m.actuator_lag + m.queue_delay);
    EXPECT_GE(m.queue_delay, 0ns);
    EXPECT_GE(m.network_delay, m.lost_packets * config.station.command_period);
  }
}

TEST(Generator, ImperfectionsAppearAtTheirRates) {
  RigConfig config = test::ideal_config(8000);
  config.cause_sensor.miss_probability = 0.05;
  config.effect_sensor.miss_probability = 0.02;
  config.effect_sensor.bounce_probability = 0.1;
  config.effect_sensor.bounce_max_extra = 3;
  config.cause_sensor.spurious_per_minute = 2;
  const Simulation run = simulate(config);
  const auto passes = static_cast<double>(run.passes.size());
  double cause_missed = 0, effect_missed = 0;
  for (const auto& p : run.passes) {
    cause_missed += p.cause_event < 0 ? 1 : 0;
    effect_missed += p.effect_event < 0 ? 1 : 0;
  }
  EXPECT_NEAR(cause_missed, passes * 0.05, 4 * binomial_sigma(passes, 0.05));
  EXPECT_NEAR(effect_missed, passes * 0.02, 4 * binomial_sigma(passes, 0.02));

  // Bounces: on the effect side only; 1..3 extra edges (mean 2) after 10% of detected passes,
  // each within the window after its pass's edge.
  std::map<std::int64_t, int> bounces_per_pass;
  double spurious = 0;
  for (const auto& t : run.cause_truth) {
    EXPECT_NE(t.kind, EdgeKind::bounce);
    spurious += t.kind == EdgeKind::spurious ? 1 : 0;
  }
  for (const auto& t : run.effect_truth) {
    EXPECT_NE(t.kind, EdgeKind::spurious);
    if (t.kind == EdgeKind::bounce) ++bounces_per_pass[t.pass];
  }
  const double detected = passes - effect_missed;
  EXPECT_NEAR(static_cast<double>(bounces_per_pass.size()), detected * 0.1,
              4 * binomial_sigma(detected, 0.1));
  double extra = 0;
  for (const auto& [pass, count] : bounces_per_pass) {
    EXPECT_GE(count, 1);
    EXPECT_LE(count, 3);
    extra += count;
  }
  EXPECT_NEAR(extra / static_cast<double>(bounces_per_pass.size()), 2.0, 0.15);

  // Spurious edges: a Poisson process at 2 per minute over the run.
  const double minutes =
      static_cast<double>(run.cause_truth.back().true_time.ns() - config.start.ns()) / 60e9;
  EXPECT_NEAR(spurious, 2 * minutes, 5 * std::sqrt(2 * minutes));
  EXPECT_EQ(run.cause_events.size() + static_cast<std::size_t>(cause_missed),
            run.passes.size() + static_cast<std::size_t>(spurious));
}

TEST(Generator, ImperfectionsDoNotMoveTheMotion) {
  RigConfig ideal = test::ideal_config(300);
  RigConfig noisy = ideal;
  noisy.effect_sensor.bounce_probability = 0.5;
  noisy.cause_sensor.spurious_per_minute = 10;
  noisy.cause_sensor.miss_probability = 0.2;
  const Simulation a = simulate(ideal);
  const Simulation b = simulate(noisy);
  EXPECT_EQ(a.manoeuvres, b.manoeuvres);
  ASSERT_EQ(a.passes.size(), b.passes.size());
  for (std::size_t i = 0; i < a.passes.size(); ++i) {
    EXPECT_EQ(a.passes[i].cause_time, b.passes[i].cause_time);
    EXPECT_EQ(a.passes[i].effect_time, b.passes[i].effect_time);
  }
}

TEST(Generator, StreamingGivesTheSameRunInBoundedChunks) {
  RigConfig config;
  config.manoeuvres = 400;
  config.magnets_deg = {0, 20, 40};
  config.effect_sensor.bounce_probability = 0.3;
  const Simulation whole = simulate(config);

  Generator generator(config);
  Chunk chunk;
  Simulation streamed;
  std::size_t chunks = 0;
  while (generator.next(chunk, 7)) {
    ++chunks;
    EXPECT_LE(chunk.event_count(), 7u);
    EXPECT_EQ(chunk.cause_first_index, static_cast<std::int64_t>(streamed.cause_events.size()));
    EXPECT_EQ(chunk.effect_first_index, static_cast<std::int64_t>(streamed.effect_events.size()));
    for (Role role : kRoles) {
      auto& events = role == Role::cause ? streamed.cause_events : streamed.effect_events;
      auto& truth = role == Role::cause ? streamed.cause_truth : streamed.effect_truth;
      events.insert(events.end(), chunk.events(role).begin(), chunk.events(role).end());
      truth.insert(truth.end(), chunk.truth(role).begin(), chunk.truth(role).end());
    }
    streamed.pairs.insert(streamed.pairs.end(), chunk.pairs.begin(), chunk.pairs.end());
    streamed.passes.insert(streamed.passes.end(), chunk.passes.begin(), chunk.passes.end());
    streamed.clock_samples.insert(streamed.clock_samples.end(), chunk.clock_samples.begin(),
                                  chunk.clock_samples.end());
  }
  EXPECT_TRUE(generator.done());
  EXPECT_FALSE(generator.next(chunk));
  EXPECT_GT(chunks, whole.cause_events.size() / 7);
  EXPECT_EQ(streamed.cause_events, whole.cause_events);
  EXPECT_EQ(streamed.effect_events, whole.effect_events);
  EXPECT_EQ(streamed.cause_truth, whole.cause_truth);
  EXPECT_EQ(streamed.effect_truth, whole.effect_truth);
  EXPECT_EQ(streamed.pairs, whole.pairs);
  EXPECT_EQ(streamed.passes, whole.passes);
  EXPECT_EQ(streamed.clock_samples, whole.clock_samples);
}

TEST(Generator, CloseMagnetsDefeatNearestNeighbourPairing) {
  RigConfig config = test::ideal_config(500);
  config.magnets_deg = {0, 20, 40};
  const Simulation run = simulate(config);
  // Within a manoeuvre the edges are tens of ms apart; the latency is hundreds of ms.
  double widest_spacing_ms = 0;
  double cause_spacing_sum = 0, effect_spacing_sum = 0;
  for (std::size_t i = 1; i < run.passes.size(); ++i) {
    const auto& a = run.passes[i - 1];
    const auto& b = run.passes[i];
    if (a.manoeuvre != b.manoeuvre) continue;
    const double cause_ms = static_cast<double>((b.cause_time - a.cause_time).count()) / 1e6;
    const double effect_ms = static_cast<double>((b.effect_time - a.effect_time).count()) / 1e6;
    EXPECT_GT(cause_ms, 10);
    widest_spacing_ms = std::max({widest_spacing_ms, cause_ms, effect_ms});
    cause_spacing_sum += cause_ms;
    effect_spacing_sum += effect_ms;
  }
  const auto latencies = test::true_latencies_ms(run);
  EXPECT_LT(widest_spacing_ms, 250);
  EXPECT_GT(test::quantile(latencies, 0), 2 * widest_spacing_ms);
  // The vehicle's actuator turns more slowly: its edges are further apart than the operator's.
  EXPECT_GT(effect_spacing_sum, 1.1 * cause_spacing_sum);
  // Pairing each effect edge with the nearest cause edge in time (after removing the median
  // latency) picks the wrong magnet pass often.
  const double median_ns = test::quantile(latencies, 0.5) * 1e6;
  std::size_t wrong = 0;
  for (const TruePair& pair : run.pairs) {
    const double target =
        static_cast<double>(run.effect_events[static_cast<std::size_t>(pair.effect_index)].time.ns()) -
        median_ns;
    std::size_t best = 0;
    double best_distance = 1e300;
    for (std::size_t j = 0; j < run.cause_events.size(); ++j) {
      const double distance = std::abs(static_cast<double>(run.cause_events[j].time.ns()) - target);
      if (distance < best_distance) {
        best_distance = distance;
        best = j;
      }
    }
    wrong += static_cast<std::int64_t>(best) != pair.cause_index ? 1 : 0;
  }
  EXPECT_GT(static_cast<double>(wrong), 0.3 * static_cast<double>(run.pairs.size()));
}

TEST(Generator, RejectsBadConfiguration) {
  RigConfig config;
  config.magnets_deg = {};
  EXPECT_THROW(Generator{config}, core::Error);
  config.magnets_deg = {0, 0};
  EXPECT_THROW(Generator{config}, core::Error);
  config.magnets_deg = {0, 355};  // span 355: even the 5-degree minimum clearance would bring a magnet round
  EXPECT_THROW(Generator{config}, core::Error);
  config = RigConfig{};
  config.manoeuvres = 0;
  EXPECT_THROW(Generator{config}, core::Error);
  config = RigConfig{};
  config.network.loss_probability = 1.5;
  try {
    Generator g(config);
    FAIL() << "accepted a loss probability of 1.5";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("network.loss_probability"), std::string::npos) << e.what();
  }
}

// SensorConfig::both_edges: the same falling edges, each pass a pulse held for its dwell, interference
// a pulse of microseconds, and every rising edge stamped after the edge before it.
TEST(Generator, BothEdgesAddPulsesAndKeepTheFallingEdges) {
  RigConfig config;
  config.manoeuvres = 200;
  config.magnets_deg = {0, 20, 40};
  for (auto* sensor : {&config.cause_sensor, &config.effect_sensor}) {
    sensor->bounce_probability = 0.2;
    sensor->spurious_per_minute = 6;
  }
  const Simulation one = simulate(config);
  config.cause_sensor.both_edges = config.effect_sensor.both_edges = true;
  const Simulation both = simulate(config);
  for (Role role : kRoles) {
    const auto& events = both.events(role);
    const auto& truth = role == Role::effect ? both.effect_truth : both.cause_truth;
    std::vector<std::int64_t> falling, falling_one;
    for (const auto& e : one.events(role)) falling_one.push_back(e.time.ns());
    std::map<EdgeKind, int> rising;
    for (std::size_t k = 0; k < events.size(); ++k) {
      if (events[k].edge == core::Edge::falling) {
        falling.push_back(events[k].time.ns());
        continue;
      }
      ++rising[truth[k].kind];
      ASSERT_GT(k, 0u);
      EXPECT_GT(events[k].time.ns(), events[k - 1].time.ns()) << k;  // stamped in the line's order
      // Interference is microseconds wide (its own falling edge just before, unless a pass came between).
      if (truth[k].kind == EdgeKind::spurious && truth[k - 1].kind == EdgeKind::spurious) {
        EXPECT_LE(truth[k].true_time.ns() - truth[k - 1].true_time.ns(), 50'000) << k;
      }
      if (truth[k].kind == EdgeKind::release) {
        EXPECT_GE(truth[k].true_time.ns() - truth[k - 1].true_time.ns(), 50'000) << k;
      }
    }
    EXPECT_EQ(falling, falling_one);
    std::int64_t passes = 0, spurious = 0;
    for (const auto& t : (role == Role::effect ? one.effect_truth : one.cause_truth)) {
      passes += t.kind == EdgeKind::pass;
      spurious += t.kind == EdgeKind::spurious;
    }
    EXPECT_EQ(rising[EdgeKind::release], passes);  // every pass released
    EXPECT_EQ(rising[EdgeKind::spurious], spurious);
    EXPECT_GT(rising[EdgeKind::bounce], 0);
  }
  // The true pairs' edges are the same falling edges, at their new indices.
  ASSERT_EQ(one.pairs.size(), both.pairs.size());
  for (std::size_t p = 0; p < one.pairs.size(); ++p)
    EXPECT_EQ(one.cause_events[static_cast<std::size_t>(one.pairs[p].cause_index)].time,
              both.cause_events[static_cast<std::size_t>(both.pairs[p].cause_index)].time);
}
