// Stage pairing: each pair joined to its markers by the rule, stages adding up to the M2M exactly,
// incomplete chains counted with their stage and reason, the per-stage statistics.
#include "m2mlat/analysis/breakdown.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/core/error.hpp"

using namespace m2mlat;
using namespace m2mlat::analysis;

namespace m2mlat::analysis::breakdown_test {

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kMs = 1'000'000;

markers::Marker mark(std::string node, std::string name, std::int64_t ns, std::string key) {
  markers::Marker m;
  m.node = std::move(node);
  m.name = std::move(name);
  m.time = core::TimePoint::from_ns(core::Clock::realtime, ns);
  m.key = std::move(key);
  return m;
}

// One event: its cause and effect edges' times (ns).
struct Edges {
  std::int64_t cause_ns, effect_ns;
};

const StageRule& three_stage_rule() {
  static const StageRule rule = parse_stage_rule(
      "operator = first operator:send after cause\n"
      "network = same key vehicle:receive\n"
      "vehicle = effect\n",
      "rule");
  return rule;
}

// Event i: cause at i s, send 3 ms + i us later (key "c<i>"), receive 20 ms after the send, effect
// at 800 ms + i ms.
std::vector<markers::Marker> chain_markers(int events) {
  std::vector<markers::Marker> out;
  for (int i = 0; i < events; ++i) {
    const std::int64_t send = i * kSecond + 3 * kMs + i * 1000;
    out.push_back(mark("operator", "send", send, "c" + std::to_string(i)));
    out.push_back(mark("vehicle", "receive", send + 20 * kMs, "c" + std::to_string(i)));
  }
  return out;
}

Breakdown break_down_all(const std::vector<Edges>& events, const StageRule& rule, const MarkerIndex& index) {
  std::vector<std::size_t> positions;
  std::vector<std::int64_t> cause_ns, effect_ns, ids;
  for (std::size_t i = 0; i < events.size(); ++i) {
    cause_ns.push_back(events[i].cause_ns);
    effect_ns.push_back(events[i].effect_ns);
    positions.push_back(i);
    ids.push_back(static_cast<std::int64_t>(i) + 1);
  }
  return break_down(cause_ns, effect_ns, core::Clock::realtime, positions, ids, rule, index);
}

TEST(Breakdown, StagesAddUpToTheM2MExactly) {
  const auto markers = chain_markers(5);
  const MarkerIndex index(markers);
  std::vector<Edges> pairs;
  for (int i = 0; i < 5; ++i) pairs.push_back({i * kSecond, i * kSecond + 800 * kMs + i * kMs});
  const auto b = break_down_all(pairs, three_stage_rule(), index);
  EXPECT_EQ(b.complete, 5u);
  EXPECT_EQ(b.incomplete, 0u);
  ASSERT_EQ(b.events.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    const auto& e = b.events[static_cast<std::size_t>(i)];
    ASSERT_TRUE(e.complete());
    ASSERT_EQ(e.stage_ns.size(), 3u);
    EXPECT_EQ(e.stage_ns[0], 3 * kMs + i * 1000);
    EXPECT_EQ(e.stage_ns[1], 20 * kMs);
    EXPECT_EQ(e.stage_ns[0] + e.stage_ns[1] + e.stage_ns[2], e.m2m_ns);
    EXPECT_EQ(e.m2m_ns, 800 * kMs + i * kMs);
    EXPECT_EQ(e.cause_id, i + 1);
  }
  ASSERT_EQ(b.stages.size(), 3u);
  EXPECT_EQ(b.stages[0].name, "operator");
  EXPECT_EQ(b.stages[1].selector, "same key vehicle:receive");
  EXPECT_DOUBLE_EQ(b.stages[0].median_ns, 3 * kMs + 2000);
  EXPECT_DOUBLE_EQ(b.stages[0].q1_ns, 3 * kMs + 1000);  // type 7 over 0, 1, 2, 3, 4 us
  EXPECT_DOUBLE_EQ(b.stages[0].q3_ns, 3 * kMs + 3000);
  EXPECT_DOUBLE_EQ(b.stages[1].median_ns, 20 * kMs);
  EXPECT_EQ(b.stages[1].min_ns, 20 * kMs);
  EXPECT_EQ(b.stages[1].max_ns, 20 * kMs);
  EXPECT_DOUBLE_EQ(b.m2m_median_ns, 802 * kMs);
  // Shares of the total add up to 1: sum of a stage / sum of the M2M.
  EXPECT_DOUBLE_EQ(b.stages[1].share, 100.0 * kMs / (5 * 802.0 * kMs));
  EXPECT_NEAR(b.stages[0].share + b.stages[1].share + b.stages[2].share, 1.0, 1e-12);
}

TEST(Breakdown, IncompleteChainsAreCountedWithTheirStageAndReason) {
  auto markers = chain_markers(6);
  // Event 1: its receive is lost. Event 2: its receive is stamped before its send (out of order).
  // Event 3: its receive is after the effect. Event 4: its send is lost, so the first send after the
  // cause is event 5's, which is after event 4's effect.
  std::erase_if(markers, [](const markers::Marker& m) {
    return (m.key == "c1" && m.name == "receive") || (m.key == "c4" && m.name == "send");
  });
  for (auto& m : markers) {
    if (m.key == "c2" && m.name == "receive") m.time = core::TimePoint::from_ns(core::Clock::realtime, 2 * kSecond + kMs);
    if (m.key == "c3" && m.name == "receive")
      m.time = core::TimePoint::from_ns(core::Clock::realtime, 3 * kSecond + 900 * kMs);
  }
  const MarkerIndex index(markers);
  std::vector<Edges> pairs;
  for (int i = 0; i < 6; ++i) pairs.push_back({i * kSecond, i * kSecond + 800 * kMs});
  const auto b = break_down_all(pairs, three_stage_rule(), index);
  EXPECT_EQ(b.complete, 2u);  // events 0 and 5
  EXPECT_EQ(b.incomplete, 4u);
  ASSERT_EQ(b.events.size(), 6u);  // none dropped
  EXPECT_EQ(b.events[1].gap, StageGap::missing);
  EXPECT_EQ(b.events[1].gap_stage, 1u);
  EXPECT_EQ(b.events[1].detail, "no vehicle:receive with key c1");
  EXPECT_EQ(b.events[1].stage_ns.size(), 1u);  // the stage before the gap is kept
  EXPECT_EQ(b.events[2].gap, StageGap::out_of_order);
  EXPECT_EQ(b.events[3].gap, StageGap::after_effect);
  EXPECT_EQ(b.events[4].gap, StageGap::after_effect);
  EXPECT_EQ(b.events[4].gap_stage, 0u);
  ASSERT_EQ(b.gaps.size(), 4u);
  EXPECT_EQ(b.gaps[0].stage, "operator");
  EXPECT_EQ(b.gaps[0].gap, StageGap::after_effect);
  EXPECT_EQ(b.gaps[0].count, 1u);
  EXPECT_EQ(b.gaps[1].stage, "network");
  EXPECT_EQ(b.gaps[1].gap, StageGap::missing);
  EXPECT_EQ(b.gaps[2].gap, StageGap::out_of_order);
  EXPECT_EQ(b.gaps[3].stage, "network");
  EXPECT_EQ(b.gaps[3].gap, StageGap::after_effect);
  // The statistics are over the complete events only.
  EXPECT_DOUBLE_EQ(b.stages[1].median_ns, 20 * kMs);
}

TEST(Breakdown, LastBeforeEffectAndFirstAfterPrevious) {
  const StageRule rule = parse_stage_rule(
      "wire = first operator:send after cause\n"
      "picked = first vehicle:tick after previous\n"
      "last_tick = last vehicle:tick before effect\n"
      "actuator = effect\n",
      "rule");
  std::vector<markers::Marker> markers = {
      mark("operator", "send", 5 * kMs, ""),       mark("vehicle", "tick", 1 * kMs, ""),
      mark("vehicle", "tick", 30 * kMs, ""),       mark("vehicle", "tick", 40 * kMs, ""),
      mark("vehicle", "tick", 900 * kMs, ""),  // after the effect: not the last before it
  };
  const MarkerIndex index(markers);
  const auto e = event_stages(0, 100 * kMs, core::Clock::realtime, rule, index);
  ASSERT_TRUE(e.complete()) << e.detail;
  EXPECT_EQ(e.stage_ns, (std::vector<std::int64_t>{5 * kMs, 25 * kMs, 10 * kMs, 60 * kMs}));
  // No markers at all: the first stage is missing.
  const MarkerIndex empty(std::span<const markers::Marker>{});
  const auto none = event_stages(0, 100 * kMs, core::Clock::realtime, rule, empty);
  EXPECT_EQ(none.gap, StageGap::missing);
  EXPECT_EQ(none.detail, "no operator:send after the cause");
  EXPECT_TRUE(std::isnan(break_down_all({{0, 1}}, rule, empty).stages[0].median_ns));
}

TEST(Breakdown, EventsOffCLOCK_REALTIMEAreRefused) {
  const MarkerIndex index(std::span<const markers::Marker>{});
  EXPECT_THROW(event_stages(0, 10, core::Clock::monotonic, three_stage_rule(), index), core::Error);
}

}  // namespace m2mlat::analysis::breakdown_test
