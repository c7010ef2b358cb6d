// Live pairing: equals `m2mlat stats` on a finished store, grows without changing settled pairs,
// waits for missing sides, and bins the histogram on aligned widths.
#include "m2mlat/collect/live_pairing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/stats/bootstrap.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

using namespace m2mlat;
using m2mlat::testing::TempDir;

namespace {

// A simulated run of `preset` with field sensor faults (misses, bounces, spurious edges).
// `magnets` > 1 gives bursts of edges on each side, the matcher's hard case.
void simulate(const std::string& path, const std::string& preset, std::int64_t manoeuvres, std::uint64_t seed,
              int magnets = 1) {
  auto store = store::Store::open(path);
  auto config = sim::preset(preset);
  config.manoeuvres = manoeuvres;
  config.seed = seed;
  config.magnets_deg.clear();
  for (int k = 0; k < magnets; ++k) config.magnets_deg.push_back(40.0 * k);
  capture::record_simulation(store, config, "live");
}

// `m2mlat stats STORE` as the CLI computes it: the flags' defaults are the library's, the bootstrap's
// too (2000 resamples, seed 1, 95 %).
analysis::ScenarioResult offline_stats(const std::string& path) {
  analysis::PipelineInputs inputs;
  inputs.inputs = {path};
  analysis::PipelineOptions options;
  options.summary.bootstrap = stats::BootstrapOptions{};
  auto results = analysis::analyse_inputs(inputs, options);
  EXPECT_EQ(results.size(), 1u);
  return results.front();
}

void expect_same_number(double a, double b) {
  if (std::isnan(a))
    EXPECT_TRUE(std::isnan(b));
  else
    EXPECT_DOUBLE_EQ(a, b);
}

}  // namespace

TEST(LivePairing, FinishedStoreEqualsOfflineStats) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  simulate(path, "static_wifi", 120, 7);
  const auto offline = offline_stats(path);

  collect::LivePairing live(path, {});
  const auto& s = live.update();
  ASSERT_EQ(s.state, collect::LiveState::ok) << s.message;
  EXPECT_EQ(s.scenario, offline.input.scenario);
  EXPECT_EQ(s.cause_ref, offline.input.cause_ref);
  EXPECT_EQ(s.effect_ref, offline.input.effect_ref);
  EXPECT_EQ(s.cause_events, offline.match.cause_count);
  EXPECT_EQ(s.effect_events, offline.match.effect_count);
  EXPECT_EQ(s.pairs, offline.match.pairs.size());
  EXPECT_EQ(s.ambiguous, offline.ambiguous_pairs());
  EXPECT_EQ(s.summary.n, offline.summary.n);
  EXPECT_GT(s.summary.n, 100u);
  expect_same_number(s.summary.median_ms, offline.summary.median_ms);
  expect_same_number(s.summary.q1_ms, offline.summary.q1_ms);
  expect_same_number(s.summary.q3_ms, offline.summary.q3_ms);
  expect_same_number(s.summary.iqr_ms, offline.summary.iqr_ms);
  expect_same_number(s.summary.mean_ms, offline.summary.mean_ms);
  expect_same_number(s.summary.p95_ms, offline.summary.p95_ms);
  EXPECT_EQ(s.summary.min, offline.summary.min);
  EXPECT_EQ(s.summary.max, offline.summary.max);
  ASSERT_TRUE(s.summary.bootstrap && offline.summary.bootstrap);  // the intervals, bit for bit
  EXPECT_EQ(s.summary.bootstrap->median_ms.lower, offline.summary.bootstrap->median_ms.lower);
  EXPECT_EQ(s.summary.bootstrap->median_ms.upper, offline.summary.bootstrap->median_ms.upper);
  EXPECT_EQ(s.summary.bootstrap->iqr_ms.lower, offline.summary.bootstrap->iqr_ms.lower);
  EXPECT_EQ(s.summary.bootstrap->iqr_ms.upper, offline.summary.bootstrap->iqr_ms.upper);
  EXPECT_LE(s.summary.bootstrap->median_ms.lower, s.summary.median_ms);
  EXPECT_GE(s.summary.bootstrap->median_ms.upper, s.summary.median_ms);
  std::size_t cause_unmatched = 0, effect_unmatched = 0, bounces = 0;
  for (const auto& u : offline.match.unmatched) {
    if (u.reason == pairing::UnmatchedReason::bounce)
      ++bounces;
    else
      ++(u.side == pairing::Side::cause ? cause_unmatched : effect_unmatched);
  }
  EXPECT_EQ(s.cause_unmatched, cause_unmatched);
  EXPECT_EQ(s.effect_unmatched, effect_unmatched);
  EXPECT_EQ(s.bounces, bounces);
  EXPECT_GT(s.bounces + s.cause_unmatched + s.effect_unmatched, 0u);  // the field sensor's faults show

  // The newest pair and the strip chart's tail are the offline pairs'.
  ASSERT_TRUE(s.last.has_value());
  const auto& last = offline.match.pairs.back();
  EXPECT_EQ(s.last->cause_ns, offline.times().cause(last));
  EXPECT_EQ(s.last->latency_ns, offline.times().latency(last).count());
  ASSERT_EQ(s.recent.size(), std::min<std::size_t>(offline.match.pairs.size(), 300));
  EXPECT_EQ(s.recent.back(), *s.last);
  // The histogram holds exactly the statistics' latencies.
  std::size_t binned = 0;
  for (const auto& b : s.histogram) binned += b.count;
  EXPECT_EQ(binned, s.summary.n);
  EXPECT_LE(s.histogram.front().lower_ns, s.summary.min->ns);
  EXPECT_GT(s.histogram.back().upper_ns, s.summary.max->ns);
}

// A vehicle clock stepped by 40 ms mid-run: the live view corrects it as `m2mlat stats` does (the
// store's clock records), so that its latencies do not jump by the step.
TEST(LivePairing, CorrectsAClockStepAsOfflineDoes) {
  using namespace std::chrono_literals;
  TempDir dir;
  const auto path = dir.file("campaign.db");
  {
    auto store = store::Store::open(path);
    auto config = sim::preset("static_wifi");
    config.manoeuvres = 60;
    config.seed = 3;
    config.effect_clock.step_at = 60s;
    config.effect_clock.step = 40ms;
    capture::record_simulation(store, config, "live");
  }
  const auto offline = offline_stats(path);
  ASSERT_GT(offline.steps.steps(), 0u);
  collect::LivePairing live(path, {});
  const auto& s = live.update();
  ASSERT_EQ(s.state, collect::LiveState::ok) << s.message;
  EXPECT_EQ(s.pairs, offline.match.pairs.size());
  EXPECT_EQ(s.summary.n, offline.summary.n);
  expect_same_number(s.summary.median_ms, offline.summary.median_ms);
  expect_same_number(s.summary.mean_ms, offline.summary.mean_ms);
  // Every pair's latency is the offline (corrected) one; more than ten pairs lie after the step.
  ASSERT_EQ(s.recent.size(), offline.match.pairs.size());
  for (std::size_t k = 0; k < s.recent.size(); ++k)
    EXPECT_EQ(s.recent[k].latency_ns, offline.times().latency(offline.match.pairs[k]).count())
        << "pair " << k;
  EXPECT_GT(offline.pairs_marked(analysis::StepMark::corrected), 10u);
}

TEST(LivePairing, RepairsOnlyWhenTheStoreChanged) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  simulate(path, "static_5g", 20, 3);
  collect::LivePairing live(path, {});
  EXPECT_EQ(live.update().pairings, 1u);
  EXPECT_GT(live.current().update_cost_ns, 0);
  EXPECT_EQ(live.update().pairings, 1u);  // nothing new: the previous result
  simulate(path, "static_5g", 5, 4);      // a second run: new sessions of the same scenario
  EXPECT_EQ(live.update().pairings, 2u);
}

// The store grows batch by batch as the coordinator would fill it; every update equals offline
// stats on the store as it is, and a pair once shown well behind the newest edge never changes.
TEST(LivePairing, GrowingStoreKeepsSettledPairs) {
  TempDir dir;
  const auto full = dir.file("full.db");
  const auto growing = dir.file("growing.db");
  simulate(full, "dynamic_co_referenced", 100, 11, 3);
  store::Options read_only;
  read_only.read_only = true;
  const auto source = store::Store::open(full, read_only);
  auto target = store::Store::open(growing);
  std::map<std::int64_t, std::int64_t> session_of;  // full's session id -> growing's
  for (auto s : source.sessions()) {
    s.end.reset();
    session_of[s.id] = target.begin_session(s);
  }
  const auto events = source.events_after(0, 1'000'000);
  ASSERT_GT(events.size(), 500u);

  collect::LivePairing live(growing, {});
  std::map<std::int64_t, std::int64_t> shown;  // cause ns -> latency ns, of pairs already settled
  std::size_t changed = 0, checked = 0;
  const std::size_t step = events.size() / 9;
  for (std::size_t at = 0; at < events.size(); at += step) {
    // Each node's events in its own commit, in seq order, as the pullers store them.
    std::map<std::int64_t, std::vector<core::Event>> batch;
    for (auto k = at; k < std::min(at + step, events.size()); ++k)
      batch[events[k].session_id].push_back(events[k].event);
    for (const auto& [session, list] : batch) target.append_events(session_of.at(session), list);

    const auto& s = live.update();
    if (s.state != collect::LiveState::ok) continue;  // one side not seen yet
    const auto offline = offline_stats(growing);
    EXPECT_EQ(s.summary.n, offline.summary.n);
    expect_same_number(s.summary.median_ms, offline.summary.median_ms);
    // Settled: the cause is more than 30 s older than the newest pair's.
    const auto settled_before = s.last->cause_ns - 30'000'000'000;
    for (const auto& p : s.recent) {
      if (p.cause_ns >= settled_before) continue;
      auto [it, fresh] = shown.emplace(p.cause_ns, p.latency_ns);
      if (!fresh) {
        ++checked;
        changed += it->second != p.latency_ns;
      }
    }
  }
  EXPECT_GT(checked, 50u);
  EXPECT_EQ(changed, 0u);
}

TEST(LivePairing, WaitsForTheStoreAndBothSides) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  collect::LivePairing live(path, {});
  EXPECT_EQ(live.update().state, collect::LiveState::waiting);
  EXPECT_NE(live.current().message.find("no store"), std::string::npos);
  auto store = store::Store::open(path);
  EXPECT_EQ(live.update().state, collect::LiveState::waiting);
  EXPECT_NE(live.current().message.find("no session"), std::string::npos);
  store::Session cause;
  cause.scenario = "bench";
  cause.node = "operator";
  cause.role = core::Role::cause;
  cause.start = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000);
  store.begin_session(cause);
  const auto& s = live.update();
  EXPECT_EQ(s.state, collect::LiveState::waiting);
  EXPECT_EQ(s.scenario, "bench");
  EXPECT_NE(s.message.find("no effect session"), std::string::npos) << s.message;
}

TEST(LivePairing, HistogramBinsAreAlignedAndHoldEverySample) {
  constexpr std::int64_t kMs = 1'000'000;
  const std::vector<std::int64_t> v{700 * kMs, 705 * kMs, 799 * kMs, 812 * kMs, 900 * kMs};
  const auto bins = collect::histogram(v, 40);
  ASSERT_FALSE(bins.empty());
  const auto width = bins.front().upper_ns - bins.front().lower_ns;
  EXPECT_EQ(width, 10 * kMs);  // range 200 ms: 5 ms bins would be 41 (140..180), 10 ms bins are 21
  std::size_t total = 0;
  for (std::size_t k = 0; k < bins.size(); ++k) {
    EXPECT_EQ(bins[k].lower_ns % width, 0);
    EXPECT_EQ(bins[k].upper_ns - bins[k].lower_ns, width);
    if (k > 0) {
      EXPECT_EQ(bins[k].lower_ns, bins[k - 1].upper_ns);
    }
    total += bins[k].count;
  }
  EXPECT_EQ(total, v.size());
  EXPECT_LE(bins.size(), 40u);
  EXPECT_TRUE(collect::histogram({}, 40).empty());
  // Negative latencies (min_latency < 0) bin below zero, not into the zero bin.
  const auto neg = collect::histogram({-3, -1, 2}, 10);
  EXPECT_EQ(neg.front().lower_ns, -3);
  EXPECT_EQ(neg.front().count, 1u);
}
