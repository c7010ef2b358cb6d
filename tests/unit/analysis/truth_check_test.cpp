// The demo's self-check: wrong pairs split by flag, the found share, and the acceptance criterion
// (no unflagged wrong pair, at least 95 % of the true pairs found).
#include "m2mlat/analysis/truth_check.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

using namespace m2mlat;
using namespace m2mlat::analysis;

namespace m2mlat::analysis::truth_check_test {

// 20 true pairs: cause i -> effect i, 800 ms apart.
std::vector<sim::TruePair> twenty_true_pairs() {
  std::vector<sim::TruePair> pairs;
  for (std::int64_t i = 0; i < 20; ++i)
    pairs.push_back({i, i, i, core::Duration{800'000'000}, core::Duration{800'000'000}});
  return pairs;
}

pairing::Pair found_pair(std::int64_t cause, std::int64_t effect, std::uint32_t flags = 0) {
  pairing::Pair p;
  p.cause_index = static_cast<std::uint32_t>(cause);
  p.effect_index = static_cast<std::uint32_t>(effect);
  p.flags = flags;
  return p;
}


TEST(TruthCheck, CountsWrongPairsByFlagAndTheFoundShare) {
  ScenarioResult result;
  for (std::int64_t i = 0; i < 19; ++i) result.match.pairs.push_back(found_pair(i, i));  // 19 of 20: 95 %
  TruthCheck check = check_against_truth(result, twenty_true_pairs());
  EXPECT_EQ(check.correct, 19);
  EXPECT_EQ(check.missed, 1);
  EXPECT_DOUBLE_EQ(check.found_percent(), 95.0);
  EXPECT_TRUE(check.passes());  // exactly at the threshold

  // A wrong pair the matcher flagged is reported, and does not fail the check.
  result.match.pairs.push_back(found_pair(19, 18, pairing::kPairAmbiguous));
  check = check_against_truth(result, twenty_true_pairs());
  EXPECT_EQ(check.wrong, 1);
  EXPECT_EQ(check.wrong_flagged, 1);
  EXPECT_EQ(check.wrong_unflagged, 0);
  EXPECT_EQ(check.wrong_clear, 0);
  EXPECT_TRUE(check.passes());

  // The same wrong pair without a flag reaches the statistics silently: the check fails.
  result.match.pairs.back().flags = 0;
  check = check_against_truth(result, twenty_true_pairs());
  EXPECT_EQ(check.wrong_unflagged, 1);
  EXPECT_EQ(check.wrong_clear, 1);
  EXPECT_FALSE(check.passes());

  // Below 95 % found fails even with no wrong pair: 18 of 20.
  result.match.pairs.resize(18);
  check = check_against_truth(result, twenty_true_pairs());
  EXPECT_EQ(check.wrong, 0);
  EXPECT_DOUBLE_EQ(check.found_percent(), 90.0);
  EXPECT_FALSE(check.passes());

  // No true pair and nothing found: nothing to fail.
  EXPECT_TRUE(check_against_truth(ScenarioResult{}, {}).passes());
}

TEST(TruthCheck, InColumnsMovesTheTruthToTheColumnsByTimestamp) {
  // Events of each node: falling edges at 100, 300, 500 ns with rising ones between (INT64_MIN);
  // the cause column lost its middle edge (dropped as interference).
  constexpr std::int64_t kRising = std::numeric_limits<std::int64_t>::min();
  const std::vector<std::int64_t> stamps{100, kRising, 300, kRising, 500, kRising};
  ScenarioInput input;
  input.cause.t_ns = {100, 500};
  input.effect.t_ns = {100, 300, 500};
  std::vector<sim::TruePair> pairs{{0, 0, 0, {}, {}}, {1, 2, 2, {}, {}}, {2, 4, 4, {}, {}}};
  const auto moved = in_columns(pairs, stamps, stamps, input);
  EXPECT_EQ(moved[0].cause_index, 0);
  EXPECT_EQ(moved[0].effect_index, 0);
  EXPECT_EQ(moved[1].cause_index, -1);  // not in its column: it can only be missed
  EXPECT_EQ(moved[1].effect_index, 1);
  EXPECT_EQ(moved[2].cause_index, 1);
  EXPECT_EQ(moved[2].effect_index, 2);
  ScenarioResult result;
  result.match.pairs = {found_pair(0, 0), found_pair(1, 2)};
  const auto check = check_against_truth(result, moved);
  EXPECT_EQ(check.correct, 2);
  EXPECT_EQ(check.missed, 1);
}

TEST(TruthCheck, AnIdealRunPairedByTheMatcherPasses) {
  auto config = sim::preset("static_5g");
  sim::clear_imperfections(config);
  const auto run = sim::simulate(config);
  auto result = analyse(from_events("static_5g", run.cause_events, run.effect_events, {}), {}, {});
  const TruthCheck check = check_against_truth(result, run.pairs);
  EXPECT_EQ(check.true_pairs, static_cast<std::int64_t>(run.pairs.size()));
  EXPECT_TRUE(check.exact());
  EXPECT_TRUE(check.passes());
}

}  // namespace m2mlat::analysis::truth_check_test
