// Network stalls and magnet layouts all round the wheel: the commands a stall held arrive in order
// after it, the vehicle repeats every sweep in the operator's order, and the truth stays exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/motion.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "sim_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::sim;
using namespace std::chrono_literals;
using core::Role;

namespace m2mlat::sim::stall_test {

RigConfig stall_config(std::int64_t manoeuvres, std::uint64_t seed) {
  RigConfig config = preset("stalls");
  config.manoeuvres = manoeuvres;
  config.seed = seed;
  return config;
}

// Every pass of the vehicle's wheel is the effect of the operator's pass of the same magnet in the
// same sweep, the wheels are at that magnet's crossing angle at the pass, and both wheels pass in the
// same order.
void expect_exact_truth(const RigConfig& config, const Simulation& run) {
  const double lo = *std::min_element(config.magnets_deg.begin(), config.magnets_deg.end());
  const double hi = *std::max_element(config.magnets_deg.begin(), config.magnets_deg.end());
  const double centre = (lo + hi) / 2;
  for (std::size_t i = 0; i < run.passes.size(); ++i) {
    const PassTruth& pass = run.passes[i];
    const ManoeuvreTruth& m = run.manoeuvres[static_cast<std::size_t>(pass.manoeuvre)];
    const double crossing = centre - config.magnets_deg[static_cast<std::size_t>(pass.magnet)];
    EXPECT_NEAR(wheel_angle_deg(m, Role::cause, pass.cause_time), crossing, 1e-3) << i;
    EXPECT_NEAR(wheel_angle_deg(m, Role::effect, pass.effect_time), crossing, 1e-3) << i;
    if (i > 0) {
      EXPECT_GT(pass.cause_time, run.passes[i - 1].cause_time) << i;
      EXPECT_GT(pass.effect_time, run.passes[i - 1].effect_time) << i;
    }
  }
  for (const TruePair& pair : run.pairs) {
    EXPECT_EQ(run.cause_truth[static_cast<std::size_t>(pair.cause_index)].pass, pair.pass);
    EXPECT_EQ(run.effect_truth[static_cast<std::size_t>(pair.effect_index)].pass, pair.pass);
  }
}


TEST(Stalls, HeldCommandsArriveInOrderAfterTheStall) {
  const RigConfig config = stall_config(600, 7);
  const Simulation run = simulate(config);
  const auto period = config.station.command_period;
  std::int64_t held = 0;
  core::Duration longest{0};
  std::int64_t last_arrival = 0;
  for (const auto& m : run.manoeuvres) {
    const std::int64_t arrival = m.start.ns() + (m.command_delay + m.network_delay).count();
    EXPECT_GT(arrival, last_arrival) << "manoeuvre " << m.index << ": a command overtook one sent before it";
    last_arrival = arrival;
    EXPECT_EQ(m.total_delay(),
              m.command_delay + m.network_delay + m.execution_delay + m.actuator_lag + m.queue_delay);
    if (m.stall_wait > 0ns) {
      ++held;
      longest = std::max(longest, m.stall_wait);
      EXPECT_EQ(m.lost_packets, 0);  // a stall queues packets; it loses none
      EXPECT_GE(m.network_delay, m.stall_wait + config.network.delay.offset);
      // A stall lasts less than 6 s; the backlog before a command drains within 6 s x drain / period.
      EXPECT_LT(m.stall_wait, 6s + 6s * config.network.stall_drain.count() / period.count());
      // The burst's set point runs ahead of the wheel: the actuator turns at its maximum speed.
      EXPECT_EQ(m.vehicle_speed_deg_s, config.vehicle.max_speed_deg_s);
    } else {
      EXPECT_LE(m.vehicle_speed_deg_s, m.operator_speed_deg_s * config.vehicle.speed_ratio_max);
    }
  }
  // 2 stalls a minute of about 3.5 s: roughly one manoeuvre in nine waits in a queue.
  EXPECT_GT(held, 30);
  EXPECT_LT(held, 150);
  EXPECT_GT(longest, 3s);
  expect_exact_truth(config, run);
  // Some effects now lie several operator edges after their cause (the matcher's hard case).
  std::int64_t most_between = 0;
  for (const TruePair& pair : run.pairs) {
    const auto effect_ns = run.effect_events[static_cast<std::size_t>(pair.effect_index)].time.ns();
    std::int64_t between = 0;
    for (std::size_t k = static_cast<std::size_t>(pair.cause_index) + 1;
         k < run.cause_events.size() && run.cause_events[k].time.ns() < effect_ns; ++k)
      ++between;
    most_between = std::max(most_between, between);
  }
  EXPECT_GE(most_between, 2);
}

TEST(Stalls, OffByDefaultAndTheyMoveNothingElse) {
  RigConfig quiet = stall_config(200, 3);
  quiet.network.stall_per_minute = 0;
  RigConfig other = quiet;
  other.network.stall = constant(2s);  // no stall rate: the length and drain change nothing
  other.network.stall_drain = 5ms;
  const Simulation a = simulate(quiet);
  const Simulation b = simulate(other);
  EXPECT_EQ(a.effect_events, b.effect_events);
  EXPECT_EQ(a.pairs, b.pairs);
  // With stalls the operator's wheel does exactly what it did without: stalls have their own stream.
  const Simulation c = simulate(stall_config(200, 3));
  EXPECT_EQ(a.cause_events, c.cause_events);
  EXPECT_NE(a.pairs, c.pairs);
}

TEST(Stalls, SettingsAreValidated) {
  RigConfig config = preset("stalls");
  EXPECT_EQ(get_field(config, "network.stall_per_minute"), "2");
  const auto refused = [&](const std::string& assignment, std::string_view field) {
    const std::vector<std::string> assignments{assignment};
    RigConfig copy = config;
    try {
      apply_overrides(copy, assignments);
      ADD_FAILURE() << assignment << " was accepted";
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_EQ(copy, config);
    }
  };
  refused("network.stall_per_minute=-1", "network.stall_per_minute");
  refused("network.stall_drain=20ms", "network.stall_drain");  // as slow as the station sends
  refused("motion.min_pause=20ms", "motion.min_pause");        // one packet: the loop could miss the rest
  const std::vector<std::string> fine{"network.stall_drain=500us", "motion.min_pause=400ms"};
  EXPECT_NO_THROW(apply_overrides(config, fine));
}

TEST(Magnets, FourRoundTheWheelAreSimulated) {
  for (const bool stalls : {false, true}) {
    RigConfig config = stalls ? stall_config(300, 11) : test::ideal_config(300, 11);
    config.magnets_deg = {0, 90, 180, 270};
    config.motion.return_probability = 0.3;  // across and back too: a stall may hold one sweep of two
    ASSERT_NO_THROW(validate(config));
    const Simulation run = simulate(config);
    std::map<std::pair<std::int64_t, int>, std::set<int>> magnets_per_sweep;
    for (const auto& p : run.passes) magnets_per_sweep[{p.manoeuvre, p.sweep}].insert(p.magnet);
    for (const auto& [key, seen] : magnets_per_sweep) EXPECT_EQ(seen.size(), 4u);
    // A sweep turns the wheel almost, never quite, a whole turn: no magnet comes round twice.
    for (const auto& m : run.manoeuvres) {
      EXPECT_GT(std::abs(m.turn_deg), 270 + 2 * config.motion.clearance_min_deg - 1e-9);
      EXPECT_LT(std::abs(m.turn_deg), 360);
    }
    if (stalls) {
      std::int64_t returns_held = 0;
      for (const auto& m : run.manoeuvres) returns_held += m.return_stall_wait > 0ns ? 1 : 0;
      EXPECT_GT(returns_held, 0);  // the case above occurred
    }
    expect_exact_truth(config, run);
  }
  // A layout that leaves no room for the smallest rest past its outermost magnet is refused.
  RigConfig config;
  config.magnets_deg = {0, 90, 180, 270, 355};
  EXPECT_THROW(validate(config), core::Error);
}

}  // namespace m2mlat::sim::stall_test
