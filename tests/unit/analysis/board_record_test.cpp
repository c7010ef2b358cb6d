// The boards' record of a store scenario, loaded once: clock series and losses as recorded, the
// per-sample uncertainty and the per-board error budget by the one rule of uncertainty.hpp.
#include "m2mlat/analysis/board_record.hpp"

#include <gtest/gtest.h>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "store_fixture.hpp"

namespace m2mlat::analysis::board_record_test {
namespace {
using namespace fixture;

store::ClockSample sample(std::int64_t session, std::int64_t t_ns, const std::string& source,
                          std::int64_t max_error_ns, std::int64_t offset_ns = 0) {
  store::ClockSample s;
  s.session_id = session;
  s.time = rt(t_ns);
  s.source = source;
  s.offset_ns = offset_ns;
  s.max_error_ns = max_error_ns;
  s.est_error_ns = max_error_ns / 4;
  s.synchronised = true;
  return s;
}

using BoardRecordTest = StoreTest;
}  // namespace

TEST_F(BoardRecordTest, OneLoadGivesSeriesLossesBoundsAndBudget) {
  auto s = store::Store::open(path_);
  const auto op =
      add_session(s, "run", "operator", core::Role::cause,
                  {edge("operator", "wheel", kT0 + 1 * kS), edge("operator", "wheel", kT0 + 5 * kS)});
  const auto veh = add_session(s, "run", "vehicle", core::Role::effect,
                               {edge("vehicle", "wheel", kT0 + 1 * kS + 800 * kMs),
                                edge("vehicle", "wheel", kT0 + 5 * kS + 850 * kMs)});
  // Another scenario's session on the same node: none of its samples or losses belong to "run".
  const auto other = add_session(s, "other", "vehicle", core::Role::effect, {edge("vehicle", "wheel", kT0)});
  // Stored out of time order; the vehicle has a step between its two samples.
  s.append_clock_samples(std::vector<store::ClockSample>{
      sample(op, kT0 + 4 * kS, "chrony", 300'000, 7), sample(op, kT0, "chrony", 100'000, 5),
      sample(veh, kT0, "chrony", 200'000), sample(veh, kT0 + 3 * kS, "step", 0),
      sample(veh, kT0 + 6 * kS, "chrony", 400'000), sample(other, kT0, "chrony", 9'000'000)});
  s.append_losses(std::vector<store::Loss>{{veh, "wheel", rt(kT0 + 2 * kS), 10, 3, "seqno_gap"},
                                           {veh, "wheel", rt(kT0 + 4 * kS), 20, 2, "seqno_gap"},
                                           {other, "wheel", rt(kT0), 1, 1, "seqno_gap"}});

  auto result = analysis::analyse(analysis::load_scenario(s, "run", {}), {}, {});
  ASSERT_EQ(result.match.pairs.size(), 2u);
  analysis::UncertaintyOptions o;
  o.kernel_max = core::Duration{10'000};
  analysis::attach_board_record(result, s, o, {});

  // Series as recorded, by node name, in time order, steps included.
  ASSERT_EQ(result.clocks.size(), 2u);
  EXPECT_EQ(result.clocks[0].node, "operator");
  EXPECT_EQ(result.clocks[0].source, "chrony");
  EXPECT_EQ(result.clocks[0].t_ns, (std::vector<std::int64_t>{kT0, kT0 + 4 * kS}));
  EXPECT_EQ(result.clocks[0].offset_ns, (std::vector<std::int64_t>{5, 7}));
  EXPECT_EQ(result.clocks[1].node, "vehicle");
  EXPECT_EQ(result.clocks[1].max_error_ns, (std::vector<std::int64_t>{200'000, 0, 400'000}));

  ASSERT_EQ(result.losses.size(), 1u);
  EXPECT_EQ(result.losses[0].node, "vehicle");
  EXPECT_EQ(result.losses[0].records, 2u);
  EXPECT_EQ(result.losses[0].events, 5u);

  // The per-pair bound is the one rule of uncertainty.hpp on the same samples.
  const auto cause = analysis::make_clock_track(
      {sample(op, kT0 + 4 * kS, "chrony", 300'000, 7), sample(op, kT0, "chrony", 100'000, 5)});
  const auto effect =
      analysis::make_clock_track({sample(veh, kT0, "chrony", 200'000), sample(veh, kT0 + 3 * kS, "step", 0),
                                  sample(veh, kT0 + 6 * kS, "chrony", 400'000)});
  ASSERT_EQ(result.uncertainty.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& p = result.match.pairs[i];
    EXPECT_EQ(result.uncertainty[i], analysis::pair_uncertainty(cause, effect, result.times().cause(p),
                                                                result.times().effect(p), o));
  }
  // Worse neighbour grown by 15 ppm: cause at +1 s -> 300 us + 45 us (3 s to the later sample).
  EXPECT_EQ(result.uncertainty[0].sync_max_ns - analysis::bound_at(effect, kT0 + 1800 * kMs, 15).max_error_ns,
            345'000);

  // The budget: the median over the two pairs of each board's own bound by the same rule.
  const auto b0 = analysis::bound_at(cause, kT0 + 1 * kS, 15).max_error_ns;
  const auto b1 = analysis::bound_at(cause, kT0 + 5 * kS, 15).max_error_ns;
  ASSERT_TRUE(result.cause_clock_ms.has_value());
  EXPECT_DOUBLE_EQ(*result.cause_clock_ms, (static_cast<double>(b0) + static_cast<double>(b1)) / 2 / 1e6);
  ASSERT_TRUE(result.effect_clock_ms.has_value());
  EXPECT_GE(*result.effect_clock_ms, 0.4);  // both vehicle pairs see the 400 us sample as a neighbour
}

TEST_F(BoardRecordTest, NoSamplesLeavesEverythingEmpty) {
  auto s = store::Store::open(path_);
  add_session(s, "run", "operator", core::Role::cause, {edge("operator", "wheel", kT0)});
  add_session(s, "run", "vehicle", core::Role::effect, {edge("vehicle", "wheel", kT0 + 800 * kMs)});
  auto result = analysis::analyse(analysis::load_scenario(s, "run", {}), {}, {});
  analysis::attach_board_record(result, s, {}, {});
  EXPECT_TRUE(result.clocks.empty());
  EXPECT_TRUE(result.losses.empty());
  EXPECT_TRUE(result.uncertainty.empty());
  EXPECT_FALSE(result.cause_clock_ms.has_value());
  EXPECT_FALSE(result.effect_clock_ms.has_value());
}

}  // namespace m2mlat::analysis::board_record_test
