// Chains of the full loop: arithmetic to the ns, incomplete chains counted by reason, and the twin's
// truth recovered.
#include "m2mlat/analysis/chains.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/analysis/chain_truth.hpp"
#include "m2mlat/sim/full_loop.hpp"

namespace m2mlat::analysis::chains_test {

namespace {

constexpr std::size_t kM2m = 0, kG2g = 1, kE2e = 2;

sim::FullLoopConfig config(int manoeuvres, std::uint64_t seed) {
  sim::FullLoopConfig c;
  c.seed = seed;
  c.manoeuvres = manoeuvres;
  return c;
}

std::size_t complete(const ChainResult& r) {
  std::size_t n = 0;
  for (const auto& c : r.chains) n += c.gap ? 0 : 1;
  return n;
}

TEST(Chains, SingleBoardArithmeticToTheNanosecond) {
  ChainInput in;
  in.single_board = true;
  in.led = {{1'000'000'000, 2'000}, {3'000'000'000, 2'000}, {5'000'000'000, 3'000}};
  in.photo_ns = {1'093'456'789, 3'101'000'001};  // the third LED's light never arrived
  ChainOptions o;
  o.uncertainty.kernel_u = core::Duration{5'000};
  o.photo_u = core::Duration{10'000};
  const auto r = build_chains(in, o, {}, "bench");
  ASSERT_EQ(r.chains.size(), 3u);
  EXPECT_EQ(r.chains[0].values[kG2g].ns, 93'456'789);
  EXPECT_EQ(r.chains[1].values[kG2g].ns, 101'000'001);
  EXPECT_FALSE(r.chains[0].gap);
  EXPECT_EQ(r.chains[2].gap, ChainGap::no_photo);
  EXPECT_EQ(r.incomplete[static_cast<std::size_t>(ChainGap::no_photo)], 1u);
  // No sync term on one board: sqrt(2000^2 / 3 + 5000^2 + 10000^2).
  EXPECT_EQ(r.chains[0].u_ns[kG2g], std::llround(std::sqrt(2000.0 * 2000.0 / 3 + 25e6 + 1e8)));
  // G2G alone in the summaries, as for the camera file; the missing one counted, not dropped.
  EXPECT_FALSE(r.loop.find(LoopQuantity::m2m));
  const auto* g2g = r.loop.find(LoopQuantity::g2g);
  ASSERT_TRUE(g2g);
  EXPECT_EQ(g2g->ns.size(), 2u);
  EXPECT_EQ(g2g->excluded[static_cast<std::size_t>(LoopExclusion::missing)], 1u);
  EXPECT_TRUE(r.loop.from_chains);
}

// A pair the matcher is not sure of (here: a second photo edge 57 ms after the first could as well be
// the LED's) leaves its chain's quantities out, counted as flagged_pair, never summarised as sure.
TEST(Chains, AFlaggedPairKeepsItsChainOutOfTheSummaries) {
  ChainInput in;
  in.single_board = true;
  in.led = {{1'000'000'000, 2'000}, {3'000'000'000, 2'000}, {5'000'000'000, 2'000}, {7'000'000'000, 2'000}};
  in.photo_ns = {1'093'000'000, 1'150'000'000, 3'095'000'000, 5'097'000'000, 7'094'000'000};
  const auto r = build_chains(in, {}, {}, "bench");
  const auto count = [&](ChainGap g) { return r.incomplete[static_cast<std::size_t>(g)]; };
  EXPECT_EQ(count(ChainGap::photo_unmatched), 1u);
  ASSERT_GE(count(ChainGap::flagged_pair), 1u);
  for (const auto& c : r.chains)
    if (c.gap == ChainGap::flagged_pair) {
      EXPECT_TRUE(c.g2g_flagged);
      EXPECT_FALSE(c.values[kG2g].ns);
    }
  const auto* g2g = r.loop.find(LoopQuantity::g2g);
  ASSERT_TRUE(g2g);
  EXPECT_EQ(g2g->ns.size(), 4u - count(ChainGap::flagged_pair));
}

TEST(Chains, TwinChainsAddUpAndRecoverTheTruth) {
  const auto run = sim::simulate_full_loop(config(12, 21));
  const auto in = chain_input(run);
  const auto r = build_chains(in, {}, {}, "twin");
  EXPECT_EQ(r.detector, "flank");
  EXPECT_EQ(complete(r), 12u);
  EXPECT_EQ(r.chains.size(), 12u);
  for (const auto& c : r.chains) {
    ASSERT_FALSE(c.gap) << key(*c.gap);
    // Every quantity is the difference of its links, to the ns.
    EXPECT_EQ(*c.values[kM2m].ns,
              r.vehicle_onsets[*c.vehicle].onset_ns - r.station_onsets[*c.station].onset_ns);
    EXPECT_EQ(*c.values[kG2g].ns, in.photo_ns[*c.photo] - in.led[*c.led].stamp_ns);
    EXPECT_EQ(*c.values[kE2e].ns, *c.values[kM2m].ns + *c.values[kG2g].ns);
    EXPECT_EQ(*c.values[static_cast<std::size_t>(LoopQuantity::vehicle_motion)].ns,
              r.vehicle_onsets[*c.vehicle].end_ns - r.vehicle_onsets[*c.vehicle].onset_ns);
    EXPECT_EQ(*c.led_lag_ns, *c.led_ns - *c.vehicle_onset_ns);
    // E2E carries no sync term: its u is below M2M's and G2G's together.
    ASSERT_TRUE(c.u_ns[kM2m] && c.u_ns[kG2g] && c.u_ns[kE2e]);
    EXPECT_LT(*c.u_ns[kE2e],
              std::hypot(static_cast<double>(*c.u_ns[kM2m]), static_cast<double>(*c.u_ns[kG2g])));
  }
  const auto check = check_chains(r, run);
  EXPECT_TRUE(check.passes());
  EXPECT_EQ(check.complete, 12u);
  // The flank detector's onsets over slow to fast motions: p5..p95 inside +-2.5 ms (docs/onset.md: its
  // p95 is 0.3 ms for fast and 2.2 ms for slow motions).
  for (const auto* side : {&check.station_onset, &check.vehicle_onset}) {
    EXPECT_LT(std::fabs(side->p5_ns), 2'500'000);
    EXPECT_LT(std::fabs(side->p95_ns), 2'500'000);
  }
  EXPECT_LT(std::fabs(check.errors[kE2e].median_ns), 500'000);
}

TEST(Chains, TruthCheckCatchesABiasAndTooFewChains) {
  const auto run = sim::simulate_full_loop(config(12, 21));
  auto in = chain_input(run);
  for (auto& t : in.photo_ns) t += 5'000'000;  // the photo edges stamped 5 ms late
  const auto late = check_chains(build_chains(in, {}, {}, "late"), run);
  EXPECT_NEAR(late.errors[kG2g].median_ns, 5'000'000, 300'000);
  EXPECT_FALSE(late.passes());
  in = chain_input(run);
  in.led.resize(10);  // 2 of 12 chains incomplete: 83 % < 95 %
  const auto few = check_chains(build_chains(in, {}, {}, "few"), run);
  EXPECT_EQ(few.complete, 10u);
  EXPECT_FALSE(few.passes());
}

TEST(Chains, IncompleteChainsCountedByTheirFirstMissingLink) {
  const auto run = sim::simulate_full_loop(config(8, 5));
  auto in = chain_input(run);
  // Manoeuvre 2's light never reaches the screen; manoeuvre 4's LED write was lost (its photo edge then
  // has no LED: counted too); the vehicle's
  // trace stops before manoeuvre 7's vehicle motion (its LED write stays: joined to no onset).
  in.photo_ns.erase(in.photo_ns.begin() + 2);
  in.led.erase(in.led.begin() + 4);
  const std::int64_t cut = run.manoeuvres[7].vehicle.onset_ns + run.vehicle_offset_ns - 50'000'000;
  std::erase_if(in.vehicle_trace.samples, [&](const core::RateSample& s) { return s.time_ns >= cut; });
  const auto r = build_chains(in, {}, {}, "gaps");
  const auto count = [&](ChainGap g) { return r.incomplete[static_cast<std::size_t>(g)]; };
  EXPECT_EQ(count(ChainGap::no_photo), 1u);
  EXPECT_EQ(count(ChainGap::no_led), 1u);
  EXPECT_EQ(count(ChainGap::no_vehicle_onset), 1u);
  EXPECT_EQ(count(ChainGap::led_unjoined), 1u);
  EXPECT_EQ(count(ChainGap::no_station_onset), 0u);
  EXPECT_EQ(count(ChainGap::photo_unmatched), 1u);
  EXPECT_EQ(complete(r), 5u);
  // Every chain is either complete or counted; the summaries count the missing values.
  std::size_t counted = 0;
  for (auto n : r.incomplete) counted += n;
  EXPECT_EQ(complete(r) + counted, r.chains.size());
  const auto* e2e = r.loop.find(LoopQuantity::e2e);
  ASSERT_TRUE(e2e);
  EXPECT_EQ(e2e->ns.size(), 5u);
  EXPECT_EQ(e2e->ns.size() + e2e->excluded_total(), r.chains.size());
  const auto* m2m = r.loop.find(LoopQuantity::m2m);
  EXPECT_EQ(m2m->ns.size(), 7u);  // all but manoeuvre 7
}

TEST(Chains, BaselineM2mNearZeroAndReferenceDetectorSelectable) {
  auto c = config(10, 33);
  c.baseline = true;
  c.sync_max_ns = 0;  // the onset term alone: no clock offset between the boards
  const auto run = sim::simulate_full_loop(c);
  const auto in = chain_input(run);
  const auto flank = check_chains(build_chains(in, {}, {}, "baseline"), run);
  EXPECT_EQ(flank.complete, 10u);
  EXPECT_LT(std::fabs(flank.errors[kM2m].median_ns), 200'000);
  ChainOptions o;
  o.detector = "reference";
  const auto r = build_chains(in, o, {}, "baseline");
  EXPECT_EQ(r.detector, "reference");
  EXPECT_EQ(r.loop.file, "chains (reference)");
  for (const auto& ch : r.chains)
    if (ch.gap) ADD_FAILURE() << key(*ch.gap);
  EXPECT_EQ(r.vehicle_onsets.size(), 10u);
  // The reference detector's fixed threshold lags: its onsets are late.
  EXPECT_GT(check_chains(r, run).vehicle_onset.median_ns, 1'000'000);
}

}  // namespace

}  // namespace m2mlat::analysis::chains_test
