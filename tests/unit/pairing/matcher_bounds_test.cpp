// The matcher's bounds: a window beyond one day is refused, one that holds more candidate pairs
// than the limit is refused before anything is allocated for them, and a window as wide as the
// limit pairs a simulated run exactly as the default window does (the reference latency counts
// only occupied bins, so its memory does not follow the window's width).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

using namespace m2mlat;

namespace {

constexpr std::int64_t kS = 1'000'000'000;

// n edges a side, one a second, each effect half a second after its cause.
std::pair<std::vector<std::int64_t>, std::vector<std::int64_t>> one_a_second(std::int64_t n) {
  std::vector<std::int64_t> causes, effects;
  for (std::int64_t i = 0; i < n; ++i) {
    causes.push_back(i * kS);
    effects.push_back(i * kS + kS / 2);
  }
  return {causes, effects};
}

std::string usage_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no core::Error thrown";
  return {};
}

TEST(MatcherBounds, AWindowBeyondOneDayIsRefused) {
  const std::vector<std::int64_t> causes{0, 10 * kS}, effects{kS, 11 * kS};
  pairing::MatchOptions o;
  o.max_latency = core::Duration{1'000'000'000 * kS};  // 10^9 s, as in the report
  EXPECT_NE(usage_error([&] {
              pairing::match(causes, effects, core::Clock::realtime, o);
            }).find("beyond the matcher's limit of +-86400.000 s"),
            std::string::npos);
  o.max_latency = pairing::kMaxLatency + core::Duration{1};
  usage_error([&] { pairing::match(causes, effects, core::Clock::realtime, o); });
  o.max_latency = core::Duration{3 * kS};
  o.min_latency = -pairing::kMaxLatency - core::Duration{1};
  usage_error([&] { pairing::match(causes, effects, core::Clock::realtime, o); });
  // The limit itself is a window like any other.
  o.min_latency = -pairing::kMaxLatency;
  o.max_latency = pairing::kMaxLatency;
  EXPECT_EQ(pairing::match(causes, effects, core::Clock::realtime, o).pairs.size(), 2u);
}

TEST(MatcherBounds, MoreCandidatePairsThanTheLimitAreRefusedAtOnce) {
  // 25,000 edges a side, one a second: with a one-day window every later effect is a candidate of
  // every cause, 3.1e8 pairs (2.5 GB of alignment), more than kMaxCandidates.
  const auto edges = one_a_second(25'000);
  const auto& causes = edges.first;
  const auto& effects = edges.second;
  pairing::MatchOptions o;
  o.max_latency = pairing::kMaxLatency;
  const auto start = std::chrono::steady_clock::now();
  const auto message = usage_error([&] { pairing::match(causes, effects, core::Clock::realtime, o); });
  EXPECT_NE(message.find("312512500 candidate pairs"), std::string::npos) << message;
  EXPECT_NE(message.find("narrow the window"), std::string::npos) << message;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(MatcherBounds, TheAlignmentModelRefusesMoreCandidatesThanItsLimitAtOnce) {
  // 5,000 edges a side, one a second, a window of 1000 s: 4.5e6 candidate pairs (about 4.5 GB of the
  // model's lattice), more than kMaxModelCandidates; the rules take them.
  const auto edges = one_a_second(5'000);
  const auto& causes = edges.first;
  const auto& effects = edges.second;
  pairing::MatchOptions o;
  o.max_latency = core::Duration{1000 * kS};
  o.method = pairing::MatchOptions::Method::model;
  const auto start = std::chrono::steady_clock::now();
  const auto message = usage_error([&] { pairing::match(causes, effects, core::Clock::realtime, o); });
  EXPECT_NE(message.find("the alignment model's limit"), std::string::npos) << message;
  EXPECT_NE(message.find("--matcher rules"), std::string::npos) << message;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
}

TEST(MatcherBounds, InPlaceTheColumnsArePutBackWhenTheWindowIsRefused) {
  // The same 25,000 edges a side with a bounce after every hundredth: the window is refused after the
  // kept edges were moved to the front of the columns, and the columns are as they were.
  std::vector<std::int64_t> causes, effects;
  for (std::int64_t i = 0; i < 25'000; ++i) {
    causes.push_back(i * kS);
    effects.push_back(i * kS + kS / 2);
    if (i % 100 == 0) causes.push_back(i * kS + 1'000'000), effects.push_back(i * kS + kS / 2 + 1'000'000);
  }
  const auto causes0 = causes, effects0 = effects;
  pairing::MatchOptions o;
  o.max_latency = pairing::kMaxLatency;
  const auto message =
      usage_error([&] { pairing::match_in_place(causes, effects, core::Clock::realtime, o); });
  EXPECT_NE(message.find("312512500 candidate pairs"), std::string::npos) << message;
  EXPECT_EQ(causes, causes0);
  EXPECT_EQ(effects, effects0);
}

TEST(MatcherBounds, AOneDayWindowPairsASimulatedRunAsTheDefaultWindowDoes) {
  const auto run = sim::simulate(sim::preset("static_wifi"));
  ASSERT_GT(run.pairs.size(), 20u);
  std::vector<std::int64_t> causes, effects;
  for (const auto& e : run.cause_events) causes.push_back(e.time.ns());
  for (const auto& e : run.effect_events) effects.push_back(e.time.ns());
  const auto narrow = pairing::match(causes, effects, core::Clock::realtime);
  pairing::MatchOptions wide;
  wide.max_latency = pairing::kMaxLatency;
  const auto result = pairing::match(causes, effects, core::Clock::realtime, wide);
  ASSERT_EQ(result.pairs.size(), narrow.pairs.size());
  for (std::size_t k = 0; k < narrow.pairs.size(); ++k) {
    EXPECT_EQ(result.pairs[k].cause_index, narrow.pairs[k].cause_index) << k;
    EXPECT_EQ(result.pairs[k].effect_index, narrow.pairs[k].effect_index) << k;
  }
}

}  // namespace
