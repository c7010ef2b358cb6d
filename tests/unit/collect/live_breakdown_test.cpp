// The live breakdown (collect/live_breakdown.hpp): markers that arrive after their pairs complete the
// chains at the next update, chains still incomplete are counted, the figure equals the offline
// breakdown (analysis::attach_breakdown over the same pairs and markers) to the nanosecond, and a
// pair past the retry window keeps its join while the markers behind every open pair are let go.
#include "m2mlat/collect/live_breakdown.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/analysis/scenario_breakdown.hpp"
#include "m2mlat/analysis/sim_markers.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "m2mlat/sim/stage_markers.hpp"
#include "sim_pairs.hpp"

using namespace m2mlat;

namespace {

const analysis::StageRule& live_rule() {
  static const analysis::StageRule rule =
      analysis::parse_stage_rule(sim::stage_rule_text("operator", "vehicle"), "rule");
  return rule;
}

struct Run {
  analysis::ScenarioResult result;  // the true pairs, all in the statistics
  std::vector<markers::Marker> markers;
};

// A simulated run's true pairs as a scenario's result, and its stage markers (`drop`: each lost
// with that chance, for incomplete chains).
Run simulated(std::int64_t manoeuvres, double drop) {
  auto config = sim::preset("static_5g");
  config.manoeuvres = manoeuvres;
  const auto run = sim::simulate(config);
  sim::StageMarkerOptions options;
  options.drop_probability = drop;
  Run out;
  out.markers = analysis::to_markers(sim::stage_markers(run, options), run.config);
  out.result.input.scenario = "live";
  out.result.input.cause.t_ns = m2mlat::testing::event_times(run.cause_events);
  out.result.input.effect.t_ns = m2mlat::testing::event_times(run.effect_events);
  for (const auto& t : run.pairs) out.result.match.pairs.push_back(m2mlat::testing::true_pair(t));
  return out;
}

void expect_same(double a, double b) {
  if (std::isnan(a))
    EXPECT_TRUE(std::isnan(b));
  else
    EXPECT_EQ(a, b);  // the same code on the same int64 ns: equal, not close
}

void expect_equal(const analysis::Breakdown& live, const analysis::Breakdown& offline) {
  EXPECT_EQ(live.complete, offline.complete);
  EXPECT_EQ(live.incomplete, offline.incomplete);
  expect_same(live.m2m_median_ns, offline.m2m_median_ns);
  expect_same(live.m2m_mean_ns, offline.m2m_mean_ns);
  ASSERT_EQ(live.stages.size(), offline.stages.size());
  for (std::size_t k = 0; k < live.stages.size(); ++k) {
    const auto &a = live.stages[k], &b = offline.stages[k];
    EXPECT_EQ(a.name, b.name);
    expect_same(a.median_ns, b.median_ns);
    expect_same(a.q1_ns, b.q1_ns);
    expect_same(a.q3_ns, b.q3_ns);
    expect_same(a.mean_ns, b.mean_ns);
    expect_same(a.share, b.share);
    EXPECT_EQ(a.min_ns, b.min_ns);
    EXPECT_EQ(a.max_ns, b.max_ns);
  }
  ASSERT_EQ(live.events.size(), offline.events.size());
  for (std::size_t i = 0; i < live.events.size(); ++i) {
    EXPECT_EQ(live.events[i].stage_ns, offline.events[i].stage_ns) << "event " << i;
    EXPECT_EQ(live.events[i].gap, offline.events[i].gap) << "event " << i;
    EXPECT_EQ(live.events[i].pair, offline.events[i].pair);
  }
  ASSERT_EQ(live.gaps.size(), offline.gaps.size());
  for (std::size_t g = 0; g < live.gaps.size(); ++g) EXPECT_EQ(live.gaps[g].count, offline.gaps[g].count);
}

analysis::Breakdown offline(analysis::ScenarioResult result, const std::vector<markers::Marker>& markers) {
  analysis::attach_breakdown(result, live_rule(), analysis::MarkerIndex(markers));
  return *result.breakdown;
}

}  // namespace

TEST(LiveBreakdown, LateMarkersCompleteTheChainsAndEqualTheOfflineBreakdown) {
  auto run = simulated(40, 0.0);
  ASSERT_GT(run.result.match.pairs.size(), 30u);
  // Pull order: the vehicle's markers first, the operator's later.
  std::vector<markers::Marker> vehicle, operator_side;
  for (const auto& m : run.markers) (m.node == "vehicle" ? vehicle : operator_side).push_back(m);
  ASSERT_FALSE(vehicle.empty());
  ASSERT_FALSE(operator_side.empty());

  collect::LiveBreakdown live(live_rule(), core::Duration(3'600'000'000'000));  // an hour: nothing frozen
  auto r = run.result;
  live.add(vehicle);
  live.update(r);
  ASSERT_TRUE(r.breakdown);
  // No operator marker yet: every chain stops at its first stage, and each is counted.
  EXPECT_EQ(r.breakdown->complete, 0u);
  EXPECT_EQ(r.breakdown->incomplete, run.result.match.pairs.size());
  ASSERT_EQ(r.breakdown->gaps.size(), 1u);
  EXPECT_EQ(r.breakdown->gaps[0].stage, "operator_software");
  EXPECT_EQ(r.breakdown->gaps[0].gap, analysis::StageGap::missing);
  expect_equal(*r.breakdown, offline(run.result, vehicle));

  live.add(operator_side);
  live.update(r);
  EXPECT_EQ(r.breakdown->complete, run.result.match.pairs.size());
  expect_equal(*r.breakdown, offline(run.result, run.markers));
}

TEST(LiveBreakdown, IncompleteChainsAreCountedAsOffline) {
  auto run = simulated(60, 0.05);
  collect::LiveBreakdown live(live_rule(), core::Duration(3'600'000'000'000));
  auto r = run.result;
  live.add(run.markers);
  live.update(r);
  const auto expected = offline(run.result, run.markers);
  EXPECT_GT(expected.incomplete, 0u);  // 5 % of the markers lost: some chains break
  EXPECT_GT(expected.complete, 0u);
  EXPECT_EQ(r.breakdown->complete + r.breakdown->incomplete, run.result.match.pairs.size());
  expect_equal(*r.breakdown, expected);
}

TEST(LiveBreakdown, PairsPastTheWindowKeepTheirJoin) {
  auto run = simulated(60, 0.0);
  const auto& pairs = run.result.match.pairs;
  ASSERT_GT(pairs.size(), 40u);
  const auto times = run.result.times();
  const auto newest = times.effect(pairs.back());
  // A window that leaves the first two thirds of the pairs behind.
  const auto middle = times.effect(pairs[pairs.size() * 2 / 3]);
  const core::Duration window(newest - middle);
  std::vector<markers::Marker> early, late;  // the first half's operator markers come late
  for (const auto& m : run.markers)
    (m.node == "operator" && m.time.ns() < middle - window.count() / 4 ? late : early).push_back(m);
  ASSERT_FALSE(late.empty());

  collect::LiveBreakdown live(live_rule(), window);
  auto r = run.result;
  live.add(early);
  live.update(r);
  const auto incomplete_before = r.breakdown->incomplete;
  EXPECT_GT(incomplete_before, 0u);
  EXPECT_GT(live.frozen(), 0u);
  EXPECT_LT(live.markers_held(), early.size());  // markers behind every open pair let go
  live.add(late);
  live.update(r);
  // The frozen chains stay as they were (every pair missing a late marker was frozen: its effect
  // lies more than a window behind the newest).
  EXPECT_EQ(r.breakdown->incomplete, incomplete_before);
  EXPECT_EQ(r.breakdown->complete + r.breakdown->incomplete, pairs.size());
  // With a window that spans the run, the same late markers complete everything.
  collect::LiveBreakdown wide(live_rule(), core::Duration(3'600'000'000'000));
  auto w = run.result;
  wide.add(early);
  wide.update(w);
  wide.add(late);
  wide.update(w);
  EXPECT_EQ(w.breakdown->incomplete, 0u);
  expect_equal(*w.breakdown, offline(run.result, run.markers));
}
