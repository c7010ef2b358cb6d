// The breakdown on the simulator: every complete event's stages add up to its M2M to the nanosecond
// and are the simulated stages (their true durations plus the boards' clock errors and interrupt
// latencies at their ends); dropped markers come back as incomplete chains, each one counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "m2mlat/analysis/breakdown.hpp"
#include "m2mlat/analysis/sim_markers.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "m2mlat/sim/stage_markers.hpp"

using namespace m2mlat;
using namespace m2mlat::analysis;

namespace m2mlat::analysis::breakdown_sim_test {

const StageRule& sim_rule() {
  static const StageRule rule = parse_stage_rule(sim::stage_rule_text("operator", "vehicle"), "rule");
  return rule;
}

sim::RigConfig small_run(const char* preset, std::int64_t manoeuvres) {
  auto config = sim::preset(preset);
  config.manoeuvres = manoeuvres;
  return config;
}

// The true pairs (the perfect matcher): their edges' times, with their pass.
struct TrueEvent {
  std::int64_t cause_ns = 0, effect_ns = 0;
  std::int64_t pass = 0;
};
std::vector<TrueEvent> true_events(const sim::Simulation& run) {
  std::vector<TrueEvent> out;
  for (const auto& t : run.pairs)
    out.push_back({run.cause_events[static_cast<std::size_t>(t.cause_index)].time.ns(),
                   run.effect_events[static_cast<std::size_t>(t.effect_index)].time.ns(), t.pass});
  return out;
}

Breakdown break_down_events(const std::vector<TrueEvent>& events, const MarkerIndex& index) {
  std::vector<std::size_t> positions;
  std::vector<std::int64_t> cause_ns, effect_ns, ids;
  for (std::size_t i = 0; i < events.size(); ++i) {
    cause_ns.push_back(events[i].cause_ns);
    effect_ns.push_back(events[i].effect_ns);
    positions.push_back(i);
    ids.push_back(events[i].pass);
  }
  return break_down(cause_ns, effect_ns, core::Clock::realtime, positions, ids, sim_rule(), index);
}

TEST(BreakdownSim, StagesAddUpToTheM2MAndMatchTheTruth) {
  for (const char* preset : {"static_5g", "dynamic_co_referenced", "stalls"}) {
    SCOPED_TRACE(preset);
    const auto run = sim::simulate(small_run(preset, 40));
    const auto stages = sim::stage_markers(run);
    EXPECT_EQ(stages.dropped, 0u);
    const auto markers = to_markers(stages, run.config);
    const MarkerIndex index(markers);
    const auto events = true_events(run);
    ASSERT_GT(events.size(), 30u);
    const auto b = break_down_events(events, index);
    EXPECT_EQ(b.complete, events.size());
    EXPECT_EQ(b.incomplete, 0u);
    for (std::size_t i = 0; i < events.size(); ++i) {
      const auto& e = b.events[i];
      ASSERT_TRUE(e.complete()) << e.detail;
      std::int64_t sum = 0;
      for (const auto s : e.stage_ns) sum += s;
      EXPECT_EQ(sum, e.m2m_ns);  // to the nanosecond
      // The truth: each boundary's stamp is its true time plus what its board's clock (and, for the
      // edges, the interrupt) added.
      const auto& pass = run.passes[static_cast<std::size_t>(events[i].pass)];
      const auto& chain = stages.chains[static_cast<std::size_t>(events[i].pass)];
      const auto& ct = run.cause_truth[static_cast<std::size_t>(pass.cause_event)];
      const auto& et = run.effect_truth[static_cast<std::size_t>(pass.effect_event)];
      std::vector<std::int64_t> stamps = {ct.true_time.ns() + ct.irq_latency.count() +
                                          ct.clock_error.count()};
      for (std::size_t k = 0; k < sim::kStageMarkerCount; ++k)
        stamps.push_back(chain.true_ns[k] + chain.clock_error_ns[k]);
      stamps.push_back(et.true_time.ns() + et.irq_latency.count() + et.clock_error.count());
      for (std::size_t k = 0; k + 1 < stamps.size(); ++k)
        EXPECT_EQ(e.stage_ns[k], stamps[k + 1] - stamps[k]) << "pass " << pass.index << " stage " << k;
      // The true stages are the manoeuvre's own delays (unless clamped at the effect).
      const auto& m = run.manoeuvres[static_cast<std::size_t>(pass.manoeuvre)];
      if (chain.true_ns[3] < pass.effect_time.ns()) {
        EXPECT_EQ(chain.true_ns[1] - pass.cause_time.ns(), m.command_delay.count());
        EXPECT_EQ(chain.true_ns[3] - chain.true_ns[2], m.execution_delay.count());
        if (pass.sweep == 0) {
          EXPECT_EQ(chain.true_ns[2] - chain.true_ns[1], m.network_delay.count());
        }
      }
    }
    // The stages' shares add up to the whole.
    double shares = 0;
    for (const auto& s : b.stages) shares += s.share;
    EXPECT_NEAR(shares, 1.0, 1e-9);
  }
}

TEST(BreakdownSim, TheFreshClockModelGivesTheEventsOwnClockErrors) {
  // The markers' stamps come from a fresh clock model of the run: it must be the one the events were
  // stamped with, or the breakdown would meet clock errors the rig never had.
  const auto run = sim::simulate(small_run("dynamic_autonomous", 30));
  struct Stamped {
    std::int64_t key_ns;
    core::Role role;
    std::int64_t error_ns;
  };
  std::vector<Stamped> edges;
  for (const auto role : {core::Role::cause, core::Role::effect})
    for (const auto& t : run.truth(role))
      edges.push_back({t.true_time.ns() + t.irq_latency.count(), role, t.clock_error.count()});
  std::ranges::stable_sort(edges, {}, &Stamped::key_ns);
  sim::ClockPair clocks(run.config.cause_clock, run.config.effect_clock, run.config.sync,
                        run.config.start.ns(), run.config.seed);
  ASSERT_GT(edges.size(), 50u);
  for (const auto& e : edges) ASSERT_EQ(clocks.error(e.role, e.key_ns).count(), e.error_ns);
}

TEST(BreakdownSim, DroppedMarkersAreIncompleteChainsWithTheRightCount) {
  const auto run = sim::simulate(small_run("static_wifi", 60));
  sim::StageMarkerOptions options;
  options.drop_probability = 0.1;
  const auto stages = sim::stage_markers(run, options);
  ASSERT_GT(stages.dropped, 5u);
  const auto markers = to_markers(stages, run.config);
  // The passes that lost any of their markers.
  std::map<std::int64_t, int> kept;
  for (const auto& m : stages.marks) ++kept[m.pass];
  const MarkerIndex index(markers);
  const auto events = true_events(run);
  std::size_t expected_incomplete = 0;
  for (const auto& e : events)
    if (kept[e.pass] < static_cast<int>(sim::kStageMarkerCount)) ++expected_incomplete;
  ASSERT_GT(expected_incomplete, 0u);
  const auto b = break_down_events(events, index);
  EXPECT_EQ(b.incomplete, expected_incomplete);
  EXPECT_EQ(b.complete + b.incomplete, events.size());
  std::size_t counted = 0;
  for (const auto& g : b.gaps) counted += g.count;
  EXPECT_EQ(counted, expected_incomplete);
  // Every complete one still adds up.
  for (const auto& e : b.events) {
    if (!e.complete()) continue;
    std::int64_t sum = 0;
    for (const auto s : e.stage_ns) sum += s;
    EXPECT_EQ(sum, e.m2m_ns);
  }
}

TEST(BreakdownSim, TheSameSeedGivesTheSameMarkers) {
  const auto run = sim::simulate(small_run("static_5g", 10));
  const auto a = sim::stage_markers(run);
  const auto b = sim::stage_markers(run);
  ASSERT_EQ(a.marks.size(), b.marks.size());
  for (std::size_t i = 0; i < a.marks.size(); ++i) EXPECT_EQ(a.marks[i].stamp, b.marks[i].stamp);
  EXPECT_THROW(sim::stage_markers(run, {1.5}), core::Error);
}

}  // namespace m2mlat::analysis::breakdown_sim_test
