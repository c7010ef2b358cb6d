// Property tests of the matcher with the simulated rig as the oracle: over many seeds and presets,
// the pairs found are compared with the simulator's true pairs.
#include <gtest/gtest.h>

#include <set>

#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

using namespace m2mlat;

namespace {

struct Score {
  std::int64_t true_pairs = 0, found = 0, correct = 0;
  std::int64_t clear = 0, clear_correct = 0;  // pairs not flagged ambiguous
  std::int64_t wrong() const { return found - correct; }
  std::int64_t missed() const { return true_pairs - correct; }
};

Score score(const sim::Simulation& run, const pairing::MatchResult& result) {
  std::set<std::pair<std::int64_t, std::int64_t>> truth;
  for (const auto& p : run.pairs) truth.emplace(p.cause_index, p.effect_index);
  Score s;
  s.true_pairs = static_cast<std::int64_t>(truth.size());
  s.found = static_cast<std::int64_t>(result.pairs.size());
  for (const auto& p : result.pairs) {
    const bool correct = truth.contains({p.cause_index, p.effect_index});
    s.correct += correct;
    if (!p.ambiguous()) ++s.clear, s.clear_correct += correct;
  }
  return s;
}

sim::RigConfig config_for(const std::string& preset, std::uint64_t seed,
                          const std::vector<std::string>& overrides) {
  auto config = sim::preset(preset);
  config.seed = seed;
  config.manoeuvres = 150;
  sim::apply_overrides(config, overrides);
  return config;
}

// The matcher's options for a simulated rig: its magnet layout, every other option at its default.
pairing::MatchOptions layout_of(const sim::RigConfig& config) {
  pairing::MatchOptions options;
  options.magnets_deg = config.magnets_deg;
  return options;
}

const std::vector<std::string> kPresets{"static_wifi", "static_5g", "dynamic_co_referenced",
                                        "dynamic_autonomous"};
const std::vector<std::vector<std::string>> kWheels{
    {"magnets_deg=0"}, {"magnets_deg=0,20,40"}, {"magnets_deg=0,15,30,45,60"}};

}  // namespace

// Clean detections: one magnet gives exactly the true pairs; with several magnets a manoeuvre whose
// latency lies far from its neighbours' may lose a pass pair to a better-fitting shifted one, which is
// then flagged (measured: 4 presets x 3 wheels x 10 seeds, 99.6 % found, no wrong pair unflagged).
TEST(MatcherProperty, CleanDetectionsGiveTheTruePairs) {
  Score total;
  for (const auto& preset : kPresets)
    for (const auto& wheel : kWheels)
      for (std::uint64_t seed = 1; seed <= 10; ++seed) {
        auto config = config_for(preset, seed, wheel);
        sim::clear_imperfections(config);
        const auto run = sim::simulate(config);
        const auto result = pairing::match(run.cause_events, run.effect_events, layout_of(config));
        const auto s = score(run, result);
        ASSERT_EQ(s.clear, s.clear_correct) << preset << " " << wheel[0] << " seed " << seed;
        if (wheel.size() == 1 && wheel[0] == "magnets_deg=0") {
          ASSERT_EQ(s.correct, s.true_pairs) << preset << " seed " << seed;
          ASSERT_EQ(s.found, s.true_pairs) << preset << " seed " << seed;
          ASSERT_TRUE(result.unmatched.empty());
        }
        total.true_pairs += s.true_pairs;
        total.correct += s.correct;
      }
  EXPECT_GT(static_cast<double>(total.correct) / static_cast<double>(total.true_pairs), 0.995);
}

// Drops, bounces and spurious edges at field rates (1 % missed passes, 3 % bounces, a spurious edge
// every 5 minutes) and at harsher rates. Pairs the matcher is not sure of are flagged (and left out of statistics by default). Stated limits (docs/matcher.md), measured over
// 4 presets x 3 wheels x 8 seeds: field: < 0.1 % of the unflagged pairs wrong, > 97 % of the true
// pairs found, > 88 % of pairs unflagged; harsh: < 0.5 % wrong among unflagged, > 85 % found, > 59.5 %
// unflagged (60.5 % before the link over a pass lost on the cause side, which finds 2 points more of the
// true pairs, flagged in their bursts, and flags 0.6 % more of the others: 59.96 %).
TEST(MatcherProperty, ImperfectDetectionsFindSurvivingPairsAndRarelyPairWrongly) {
  struct Level {
    const char* name;
    std::vector<std::string> overrides;
    double max_clear_wrong, min_found, min_clear_share;
  };
  const std::vector<Level> levels{
      {"field",
       {"sensor.miss_probability=0.01", "sensor.bounce_probability=0.03", "sensor.spurious_per_minute=0.2"},
       0.001,
       0.97,
       0.88},
      {"harsh",
       {"sensor.miss_probability=0.05", "sensor.bounce_probability=0.2", "sensor.spurious_per_minute=1"},
       0.005,
       0.85,
       0.595}};
  for (const auto& level : levels) {
    Score total;
    for (const auto& preset : kPresets)
      for (const auto& wheel : kWheels)
        for (std::uint64_t seed = 1; seed <= 8; ++seed) {
          auto overrides = wheel;
          overrides.insert(overrides.end(), level.overrides.begin(), level.overrides.end());
          const auto config = config_for(preset, seed, overrides);
          const auto run = sim::simulate(config);
          const auto s = score(run, pairing::match(run.cause_events, run.effect_events, layout_of(config)));
          total.true_pairs += s.true_pairs;
          total.found += s.found;
          total.correct += s.correct;
          total.clear += s.clear;
          total.clear_correct += s.clear_correct;
        }
    const double wrong = static_cast<double>(total.wrong()) / static_cast<double>(total.found);
    const double found = static_cast<double>(total.correct) / static_cast<double>(total.true_pairs);
    const double clear_wrong =
        static_cast<double>(total.clear - total.clear_correct) / static_cast<double>(total.clear);
    const double clear_share = static_cast<double>(total.clear) / static_cast<double>(total.found);
    RecordProperty(std::string(level.name) + "_wrong_rate", std::to_string(wrong));
    RecordProperty(std::string(level.name) + "_found_rate", std::to_string(found));
    std::printf(
        "%s: %lld true pairs, %lld found, %lld wrong (%.3f %%), %.3f %% of true pairs found; "
        "%.2f %% not ambiguous, of which %.3f %% wrong\n",
        level.name, static_cast<long long>(total.true_pairs), static_cast<long long>(total.found),
        static_cast<long long>(total.wrong()), 100 * wrong, 100 * found, 100 * clear_share,
        100 * clear_wrong);
    EXPECT_LT(clear_wrong, level.max_clear_wrong) << level.name;
    EXPECT_GT(found, level.min_found) << level.name;
    EXPECT_GT(clear_share, level.min_clear_share) << level.name;
  }
}

TEST(MatcherProperty, Deterministic) {
  auto config = config_for("static_wifi", 7, {"magnets_deg=0,20,40", "sensor.miss_probability=0.05"});
  const auto run = sim::simulate(config);
  const auto a = pairing::match(run.cause_events, run.effect_events);
  const auto b = pairing::match(run.cause_events, run.effect_events);
  EXPECT_EQ(a.pairs, b.pairs);
  EXPECT_EQ(a.unmatched, b.unmatched);
}

// Every input edge ends up exactly once in a pair or in the unmatched list, under its own input
// index and with its own timestamp, whatever the bounces removed before pairing.
TEST(MatcherProperty, EveryEdgeOnceWithItsInputIndexAndTime) {
  for (const auto& wheel : kWheels) {
    const auto run = sim::simulate(config_for(
        "static_5g", 11, {wheel.front(), "sensor.bounce_probability=0.3", "sensor.miss_probability=0.05"}));
    std::vector<std::int64_t> c, e;
    for (const auto& ev : run.cause_events) c.push_back(ev.time.ns());
    for (const auto& ev : run.effect_events) e.push_back(ev.time.ns());
    const auto result = pairing::match(c, e, core::Clock::realtime);
    std::vector<int> seen_c(c.size(), 0), seen_e(e.size(), 0);
    std::int64_t bounces = 0;
    for (const auto& p : result.pairs) {
      ASSERT_LT(static_cast<std::size_t>(p.cause_index), c.size());
      ASSERT_LT(static_cast<std::size_t>(p.effect_index), e.size());
      ++seen_c[static_cast<std::size_t>(p.cause_index)];
      ++seen_e[static_cast<std::size_t>(p.effect_index)];
    }
    for (const auto& u : result.unmatched) {
      const auto& times = u.side == pairing::Side::cause ? c : e;
      auto& seen = u.side == pairing::Side::cause ? seen_c : seen_e;
      ASSERT_LT(static_cast<std::size_t>(u.index), times.size());
      ++seen[static_cast<std::size_t>(u.index)];
      bounces += u.reason == pairing::UnmatchedReason::bounce;
    }
    EXPECT_GT(bounces, 0) << wheel.front();
    for (const int n : seen_c) EXPECT_EQ(n, 1);
    for (const int n : seen_e) EXPECT_EQ(n, 1);
  }
}
