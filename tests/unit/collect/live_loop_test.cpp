// The live view of a full-loop campaign: a store with gyroscope traces gives M2M, G2G and E2E (n,
// median, P95, last) over the traces' recent window, equal to the offline chains where the window
// holds the whole run; it waits for the second board; the snapshot and the terminal block carry them.
#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/analysis/store_chains.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/collect/dashboard.hpp"
#include "m2mlat/collect/live_pairing.hpp"
#include "m2mlat/collect/terminal_view.hpp"
#include "m2mlat/sim/full_loop.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

using namespace m2mlat;
using m2mlat::testing::TempDir;

namespace {

sim::FullLoopRun loop_run(int manoeuvres) {
  sim::FullLoopConfig c;
  c.seed = 5;
  c.manoeuvres = manoeuvres;
  return sim::simulate_full_loop(c);
}

}  // namespace

TEST(LiveLoop, AFinishedStoreGivesTheOfflineChains) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  {
    auto store = store::Store::open(path);
    capture::record_full_loop(store, loop_run(12), capture::FullLoopBoards::both, "live", "loop");
  }
  collect::LivePairing live(path, {});
  const auto& s = live.update();
  ASSERT_EQ(s.state, collect::LiveState::ok) << s.message;
  ASSERT_TRUE(s.loop);
  EXPECT_EQ(s.loop->chains, 12u);  // the run (30 to 47 s) lies inside the default 1 min window

  // Offline: the whole store, no window.
  const auto store = store::Store::open(path);
  const auto offline = analysis::build_chains(analysis::chain_input(store, "loop", {}).input, {}, {}, "loop");
  for (std::size_t q = 0; q < 3; ++q) {
    const auto& series = *offline.loop.quantities[q];
    EXPECT_EQ(s.loop->quantities[q].n, 12u) << q;
    EXPECT_DOUBLE_EQ(s.loop->quantities[q].median_ms, series.summary.median_ms) << q;
    EXPECT_DOUBLE_EQ(s.loop->quantities[q].p95_ms, series.summary.p95_ms) << q;
    EXPECT_EQ(s.loop->quantities[q].last_ns, series.ns.back()) << q;
  }

  // The snapshot and the terminal block show them side by side.
  const auto snap = collect::snapshot_json(s, {}, 0);
  const auto& loop = snap["summary"]["full_loop"];
  EXPECT_EQ(loop["e2e"]["n"], 12);
  EXPECT_DOUBLE_EQ(loop["g2g"]["median_ms"].get<double>(), s.loop->quantities[1].median_ms);
  EXPECT_EQ(loop["incomplete_chains"]["no_led"], 0);
  const auto lines = collect::render_block(s, {}, 0);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_NE(
      lines[0].find("full loop station/gyro -> vehicle/gyro (12 chains over the last 60 s, flank onsets)"),
      std::string::npos)
      << lines[0];
  EXPECT_NE(lines[1].find("M2M n 12  median"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("E2E n 12"), std::string::npos) << lines[1];
  EXPECT_EQ(lines[2], "incomplete chains: none");
}

TEST(LiveLoop, TheWindowBoundsWhatEachUpdateReads) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  const auto run = loop_run(12);
  {
    auto store = store::Store::open(path);
    capture::record_full_loop(store, run, capture::FullLoopBoards::both, "live", "loop");
  }
  collect::LiveOptions options;
  options.loop_window = core::Duration{15'000'000'000};
  collect::LivePairing live(path, options);
  const auto& s = live.update();
  ASSERT_TRUE(s.loop) << s.message;
  // A manoeuvre takes 1.9 to 3.7 s with its rest; chains in the window's first 3 s are left out (a
  // link may have been cut off): the other 12 s hold 2 to 7 of the 12, never all.
  EXPECT_GE(s.loop->chains, 2u);
  EXPECT_LT(s.loop->chains, 12u);
  EXPECT_EQ(s.loop->window_ns, 15'000'000'000);
  // The newest chain is the run's last: its E2E is the offline last one.
  const auto store = store::Store::open(path);
  const auto offline = analysis::build_chains(analysis::chain_input(store, "loop", {}).input, {}, {}, "loop");
  EXPECT_EQ(s.loop->quantities[2].last_ns, offline.loop.quantities[2]->ns.back());
}

TEST(LiveLoop, WaitsForTheSecondBoardThenChains) {
  TempDir dir;
  const auto path = dir.file("campaign.db");
  const auto run = loop_run(5);
  auto store = store::Store::open(path);
  capture::record_full_loop(store, run, capture::FullLoopBoards::station, "live", "loop");
  collect::LivePairing live(path, {});
  const auto first = live.update();
  EXPECT_EQ(first.state, collect::LiveState::waiting);
  EXPECT_NE(first.message.find("has no vehicle"), std::string::npos) << first.message;
  capture::record_full_loop(store, run, capture::FullLoopBoards::vehicle, "live", "loop");
  const auto& second = live.update();
  ASSERT_EQ(second.state, collect::LiveState::ok) << second.message;
  ASSERT_TRUE(second.loop);
  EXPECT_EQ(second.loop->quantities[0].n, 5u);
  EXPECT_EQ(second.loop->quantities[2].n, 5u);
}
