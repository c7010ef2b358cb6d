// The sanity verdict: roles that look swapped, and no pairs at all.
#include "m2mlat/analysis/sanity.hpp"

#include <gtest/gtest.h>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::analysis::sanity_test {

std::vector<std::string> codes(const ScenarioResult& r) {
  std::vector<std::string> out;
  for (const auto& w : r.warnings) out.push_back(w.code);
  return out;
}

TEST(Sanity, SwappedRolesAreSaidWithBothDirectionsFigures) {
  for (const char* preset : {"static_5g", "static_wifi", "dynamic_autonomous", "stalls"}) {
    auto config = sim::preset(preset);
    const auto run = sim::simulate(config);
    const auto given = analyse(from_events(preset, run.cause_events, run.effect_events, {}), {}, {});
    EXPECT_TRUE(given.warnings.empty()) << preset << ": " << given.warnings.front().text;
    const auto swapped = analyse(from_events(preset, run.effect_events, run.cause_events, {}), {}, {});
    ASSERT_EQ(codes(swapped), std::vector<std::string>{"roles_swapped"}) << preset;
    EXPECT_NE(swapped.warnings[0].text.find("reversed (operator/"), std::string::npos) << swapped.warnings[0].text;
  }
}

TEST(Sanity, SteeringThatNeverRestsIsToldByWhichSideMovesFirst) {
  auto config = sim::preset("static_5g");
  config.motion.min_pause = core::Duration{0};
  config.motion.interval_min = core::Duration{450'000'000};
  config.motion.interval_max = core::Duration{700'000'000};
  config.motion.hold_min = config.motion.hold_max = core::Duration{0};
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    config.seed = seed;
    const auto run = sim::simulate(config);
    EXPECT_TRUE(analyse(from_events("s", run.cause_events, run.effect_events, {}), {}, {}).warnings.empty()) << seed;
    EXPECT_EQ(codes(analyse(from_events("s", run.effect_events, run.cause_events, {}), {}, {})),
              std::vector<std::string>{"roles_swapped"})
        << seed;
  }
}

TEST(Sanity, NoPairAtAllIsSaid) {
  auto config = sim::preset("static_5g");
  config.manoeuvres = 20;
  const auto run = sim::simulate(config);
  pairing::MatchOptions narrow;
  narrow.max_latency = core::Duration{1'000'000};  // 1 ms: no latency of the run fits
  const auto r = analyse(from_events("s", run.cause_events, run.effect_events, {}), narrow, {});
  EXPECT_EQ(codes(r), std::vector<std::string>{"no_pairs"});
}

}  // namespace m2mlat::analysis::sanity_test
