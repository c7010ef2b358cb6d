#include "m2mlat/analysis/selection.hpp"

#include <gtest/gtest.h>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/core/error.hpp"
#include "store_fixture.hpp"

namespace m2mlat::analysis::selection_test {
namespace {
using namespace fixture;
using SelectionTest = StoreTest;
}  // namespace

TEST_F(SelectionTest, LoadsBothSidesByRoleAndPairs) {
  auto s = store::Store::open(path_);
  // Stored out of time order on purpose: the loader sorts.
  add_session(s, "run", "operator", core::Role::cause,
              {edge("operator", "wheel", kT0 + 3000 * kMs), edge("operator", "wheel", kT0)});
  add_session(s, "run", "vehicle", core::Role::effect,
              {edge("vehicle", "wheel", kT0 + 800 * kMs), edge("vehicle", "wheel", kT0 + 3850 * kMs),
               edge("vehicle", "wheel", kT0 + 3900 * kMs, core::Edge::rising)});
  const auto input = analysis::load_scenario(s, "run", {});
  EXPECT_EQ(input.cause_ref, (core::ChannelRef{"operator", "wheel"}));
  EXPECT_EQ(input.effect_ref, (core::ChannelRef{"vehicle", "wheel"}));
  EXPECT_EQ(input.cause.t_ns, (std::vector<std::int64_t>{kT0, kT0 + 3000 * kMs}));
  EXPECT_EQ(input.effect.t_ns.size(), 2u);  // the rising edge is not selected by default
  const auto result = analysis::analyse(input, {}, {});
  ASSERT_EQ(result.summary.n, 2u);
  EXPECT_DOUBLE_EQ(result.summary.median_ms, 825.0);
  // min/max name the cause event's store seq
  EXPECT_EQ(result.summary.min->id, input.cause.seq[0]);
  EXPECT_EQ(analysis::scenarios(s), (std::vector<std::string>{"run"}));
}

TEST_F(SelectionTest, ClearErrors) {
  auto s = store::Store::open(path_);
  add_session(s, "one-sided", "operator", core::Role::cause, {edge("operator", "wheel", kT0)});
  try {
    analysis::load_scenario(s, "one-sided", {});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("no effect session"), std::string::npos) << e.what();
  }
  EXPECT_THROW(analysis::load_scenario(s, "missing", {}), core::Error);

  add_session(s, "two-channels", "operator", core::Role::cause,
              {edge("operator", "wheel", kT0), edge("operator", "pedal", kT0 + 1)});
  add_session(s, "two-channels", "vehicle", core::Role::effect, {edge("vehicle", "wheel", kT0 + 800 * kMs)});
  try {
    analysis::load_scenario(s, "two-channels", {});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("several channels"), std::string::npos) << e.what();
  }
  analysis::Selection chosen;
  chosen.cause = core::ChannelRef{"operator", "wheel"};
  EXPECT_EQ(analysis::load_scenario(s, "two-channels", chosen).cause.t_ns.size(), 1u);

  add_session(s, "clocks", "operator", core::Role::cause,
              {edge("operator", "wheel", 5, core::Edge::falling, core::Clock::monotonic)});
  add_session(s, "clocks", "vehicle", core::Role::effect, {edge("vehicle", "wheel", kT0)});
  try {
    analysis::load_scenario(s, "clocks", {});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("monotonic"), std::string::npos) << e.what();
  }
}

TEST(FromEvents, SplitsByNodeAndRefusesMixedChannels) {
  std::vector<core::Event> events{edge("operator", "wheel", kT0), edge("vehicle", "wheel", kT0 + 900 * kMs)};
  analysis::Selection sel;
  sel.cause = core::ChannelRef{"operator", ""};
  sel.effect = core::ChannelRef{"vehicle", ""};
  const auto input = analysis::from_events("x", events, events, sel);
  EXPECT_EQ(input.cause.t_ns.size(), 1u);
  EXPECT_EQ(input.effect.t_ns.size(), 1u);
  events.push_back(edge("vehicle", "pedal", kT0 + 950 * kMs));
  EXPECT_THROW(analysis::from_events("x", events, events, sel), core::Error);
}

// Two passes a side (the line held low for 12 ms) and a 5 us pulse of interference on the vehicle's
// line, 300 ms after the operator's second pass, where its pass was missed.
std::vector<core::Event> passes_and_interference() {
  const auto pass = [](const char* node, std::int64_t t, std::vector<core::Event>& out) {
    out.push_back(edge(node, "wheel", t));
    out.push_back(edge(node, "wheel", t + 12 * kMs, core::Edge::rising));
  };
  std::vector<core::Event> events;
  pass("operator", kT0, events);
  pass("vehicle", kT0 + 800 * kMs, events);
  pass("operator", kT0 + 3 * kS, events);
  events.push_back(edge("vehicle", "wheel", kT0 + 3300 * kMs));
  events.push_back(edge("vehicle", "wheel", kT0 + 3300 * kMs + 5'000, core::Edge::rising));
  return events;
}

TEST(FromEvents, MinPulseDropsInterferenceAndKeepsIds) {
  const auto events = passes_and_interference();
  analysis::Selection sel;
  sel.cause = core::ChannelRef{"operator", ""};
  sel.effect = core::ChannelRef{"vehicle", ""};
  sel.auto_min_pulse = false;
  EXPECT_EQ(analysis::from_events("x", events, events, sel).effect.t_ns.size(), 2u);  // filter off
  EXPECT_FALSE(analysis::from_events("x", events, events, sel).glitches);
  // The default: 1 ms (kAutoMinPulse) since both lines hold both edges.
  sel.auto_min_pulse = true;
  EXPECT_EQ(analysis::from_events("x", events, events, sel).glitches->min_pulse, analysis::kAutoMinPulse);
  sel.min_pulse = core::Duration{kMs};
  const auto input = analysis::from_events("x", events, events, sel);
  EXPECT_EQ(input.cause.t_ns, (std::vector<std::int64_t>{kT0, kT0 + 3 * kS}));
  EXPECT_EQ(input.effect.t_ns, (std::vector<std::int64_t>{kT0 + 800 * kMs}));
  EXPECT_EQ(input.effect.seq, (std::vector<std::int64_t>{2}));  // its index in the file's events
  ASSERT_TRUE(input.glitches);
  EXPECT_EQ(input.glitches->cause, 0);
  EXPECT_EQ(input.glitches->effect, 1);
}

TEST(FromEvents, MinPulseNeedsBothEdgesAndOneKindToPair) {
  analysis::Selection sel;
  sel.cause = core::ChannelRef{"operator", ""};
  sel.effect = core::ChannelRef{"vehicle", ""};
  sel.min_pulse = core::Duration{kMs};
  const std::vector<core::Event> falling_only{edge("operator", "wheel", kT0),
                                              edge("vehicle", "wheel", kT0 + 900 * kMs)};
  try {
    analysis::from_events("x", falling_only, falling_only, sel);
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("operator/wheel has falling edges only"), std::string::npos)
        << e.what();
  }
  sel.edge.reset();
  const auto events = passes_and_interference();
  try {
    analysis::from_events("x", events, events, sel);
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
  }
}

TEST_F(SelectionTest, MinPulseOnAStore) {
  auto s = store::Store::open(path_);
  std::vector<core::Event> operator_edges, vehicle_edges;
  for (auto& e : passes_and_interference())
    (e.node == "operator" ? operator_edges : vehicle_edges).push_back(e);
  add_session(s, "run", "operator", core::Role::cause, operator_edges);
  add_session(s, "run", "vehicle", core::Role::effect, vehicle_edges);
  analysis::Selection sel;
  sel.min_pulse = core::Duration{kMs};
  const auto input = analysis::load_scenario(s, "run", sel);
  EXPECT_EQ(input.effect.t_ns, (std::vector<std::int64_t>{kT0 + 800 * kMs}));
  ASSERT_TRUE(input.glitches);
  EXPECT_EQ(input.glitches->effect, 1);
  const auto result = analysis::analyse(input, {}, {});
  EXPECT_EQ(result.summary.n, 1u);  // without the filter the interference pairs at 300 ms
  analysis::Selection off;
  off.auto_min_pulse = false;
  EXPECT_EQ(analysis::analyse(analysis::load_scenario(s, "run", off), {}, {}).summary.n, 2u);
  // The default filters as 1 ms does: both lines hold both edges.
  EXPECT_EQ(analysis::analyse(analysis::load_scenario(s, "run", {}), {}, {}).summary.n, 1u);
}

TEST(FromTimestamps, FilesInTimeOrderKeepNoSeqColumn) {
  analysis::SideInput cause{{"cause", "gpio16"}, {kT0, kT0 + 3000 * kMs}};
  analysis::SideInput effect{{"effect", "gpio16"}, {kT0 + 800 * kMs, kT0 + 3850 * kMs}};
  const auto input = analysis::from_timestamps("x", std::move(cause), std::move(effect));
  EXPECT_TRUE(input.cause.seq.empty());  // the id of a timestamp is its position
  EXPECT_TRUE(input.effect.seq.empty());
  EXPECT_EQ(input.id_kind, "index");
  EXPECT_EQ(analysis::source_id(input.cause, 1), 1);
  const auto result = analysis::analyse(input, {}, {});
  ASSERT_EQ(result.summary.n, 2u);
  EXPECT_EQ(result.summary.min->id, 0);  // 800 ms: the first cause
  EXPECT_EQ(result.summary.max->id, 1);  // 850 ms
  EXPECT_EQ(result.effect_seq(result.match.pairs[1]), 1);
}

TEST(FromTimestamps, UnsortedFilesKeepTheirPositionsAsIds) {
  // The second line of the cause file is the earlier edge: after sorting, ids are the lines' positions.
  analysis::SideInput cause{{"cause", "gpio16"}, {kT0 + 3000 * kMs, kT0, kT0 + 6000 * kMs}};
  analysis::SideInput effect{{"effect", "gpio16"}, {kT0 + 800 * kMs, kT0 + 3850 * kMs, kT0 + 6900 * kMs}};
  const auto input = analysis::from_timestamps("x", std::move(cause), std::move(effect));
  EXPECT_EQ(input.cause.t_ns, (std::vector<std::int64_t>{kT0, kT0 + 3000 * kMs, kT0 + 6000 * kMs}));
  EXPECT_EQ(input.cause.seq, (std::vector<std::int64_t>{1, 0, 2}));
  EXPECT_TRUE(input.effect.seq.empty());
  const auto result = analysis::analyse(input, {}, {});
  ASSERT_EQ(result.summary.n, 3u);
  EXPECT_EQ(result.summary.min->id, 1);  // 800 ms, the cause on the file's second line
  EXPECT_EQ(result.summary.max->id, 2);  // 900 ms
}

TEST(Summarize, ExtremesNameTheCauseOfPairsInTheStatistics) {
  // Latencies 500, 100 (ambiguous, left out), 300, 100, 900, 900 ms: the ids of the extremes are the
  // causes' seq, counted over the pairs in the statistics only; ties go to the earlier pair.
  analysis::ScenarioResult r;
  r.input.cause.seq = {70, 71, 72, 73, 74, 75};
  r.input.effect.seq = {80, 81, 82, 83, 84, 85};
  const std::int64_t latency_ms[] = {500, 100, 300, 100, 900, 900};
  for (std::int64_t i = 0; i < 6; ++i) {
    pairing::Pair p;
    p.cause_index = p.effect_index = static_cast<std::uint32_t>(i);
    if (i == 1) p.flags = pairing::kPairAmbiguous;
    r.input.cause.t_ns.push_back(kT0 + i * 10'000 * kMs);
    r.input.effect.t_ns.push_back(r.input.cause.t_ns.back() + latency_ms[i] * kMs);
    r.match.pairs.push_back(p);
  }
  analysis::summarize(r, {});
  ASSERT_EQ(r.summary.n, 5u);
  EXPECT_EQ(r.summary.min->id, 73);
  EXPECT_EQ(r.summary.min->index, 2u);  // position among the latencies summarised
  EXPECT_EQ(r.summary.max->id, 74);
  r.include_ambiguous = true;
  analysis::summarize(r, {});
  EXPECT_EQ(r.summary.min->id, 71);
  EXPECT_EQ(r.summary.max->id, 74);
  EXPECT_EQ(r.latencies_ns().front(), 500 * kMs);  // the result's pairs are not reordered
}

}  // namespace m2mlat::analysis::selection_test
