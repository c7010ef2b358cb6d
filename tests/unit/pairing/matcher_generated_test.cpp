// The matcher on generated logs whose true pairs are known (generated_logs.hpp), with DEFAULT options
// (and the magnet layout): stalls of up to 6 s, lost, bouncing and spurious edges, clock steps of
// +-40 ms, wheels with 1-4 magnets. The promise tested: no wrong pair reaches the statistics unflagged,
// and at least 95 % of the true pairs are found.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include "generated_logs.hpp"
#include "m2mlat/pairing/matcher.hpp"

namespace m2mlat::pairing::generated_test {

using generated::LogOptions;

struct Tally {
  std::int64_t true_pairs = 0, pairs = 0, found = 0, wrong_clear = 0, wrong_flagged = 0, clear = 0;
  // Of wrong_clear: pairs that took an edge less than kBounceSpanLimit from the true one on one side
  // (a spurious edge just before a true one, which the refractory filter then drops as a bounce): the
  // latency is off by less than that, which the pair's worst-case bound includes (docs/matcher.md).
  std::int64_t wrong_clear_in_cluster = 0;
  // Of the rest: coincidences, pairs of two edges whose true partners are both missing or unpaired (a
  // lost edge's place taken by an unrelated edge, which nothing in a one-edge-per-pass log tells from a
  // true pair); the others took a true partner of a neighbouring pair (a chain shifted by one edge).
  std::int64_t wrong_clear_coincident = 0;
  int runs = 0, most_between = 0;
};

void run_into(Tally& t, const LogOptions& options) {
  const auto log = generated::generate(options);
  MatchOptions match_options;
  match_options.magnets_deg = options.magnets_deg;
  const auto result = match(log.cause, log.effect, core::Clock::realtime, match_options);
  ++t.runs;
  t.most_between = std::max(t.most_between, log.max_edges_between);
  t.true_pairs += static_cast<std::int64_t>(log.truth.size());
  std::map<std::int64_t, std::int64_t> effect_of, cause_of;  // the true pairs, both ways
  for (const auto& [c, e] : log.truth) effect_of[c] = e, cause_of[e] = c;
  std::set<std::int64_t> paired_causes, paired_effects;
  for (const auto& p : result.pairs)
    paired_causes.insert(p.cause_index), paired_effects.insert(p.effect_index);
  const auto near = [](std::int64_t a, std::int64_t b) { return std::abs(a - b) < kBounceSpanLimit.count(); };
  for (const auto& p : result.pairs) {
    ++t.pairs;
    const bool right = log.truth.contains({p.cause_index, p.effect_index});
    t.found += right;
    if (!p.ambiguous()) ++t.clear;
    if (!right) (p.ambiguous() ? t.wrong_flagged : t.wrong_clear) += 1;
    if (right || p.ambiguous()) continue;
    const auto e = effect_of.find(p.cause_index);
    const auto c = cause_of.find(p.effect_index);
    const auto at = [](const std::vector<std::int64_t>& v, std::int64_t k) { return v[static_cast<std::size_t>(k)]; };
    if ((e != effect_of.end() && near(at(log.effect, e->second), at(log.effect, p.effect_index))) ||
        (c != cause_of.end() && near(at(log.cause, c->second), at(log.cause, p.cause_index))))
      ++t.wrong_clear_in_cluster;
    else if ((e == effect_of.end() || !paired_effects.contains(e->second)) &&
             (c == cause_of.end() || !paired_causes.contains(c->second)))
      ++t.wrong_clear_coincident;
  }
}

// What a kind of log must show: the promise (no wrong pair unflagged, 95 % of the true pairs found),
// or, where the matcher does not keep it yet (docs/matcher.md, "Open"), the figures measured, so that
// they can only get better.
struct Bound {
  std::int64_t max_wrong_clear = 0;
  double min_found_pct = 95.0;
  double min_clear_pct = 0;  // true pairs found and not flagged: what reaches the statistics
  // Of max_wrong_clear, at most this many neither within 3 ms nor coincident (-1: not checked apart).
  std::int64_t max_wrong_clear_shifted = -1;
};
constexpr Bound kPromise{};

// Runs `seeds` logs of one kind and checks the bound; prints the tally (the figures of docs/matcher.md).
void expect_promise(const std::string& name, LogOptions options, int seeds, Bound bound = kPromise) {
  Tally t;
  for (int s = 1; s <= seeds; ++s) {
    options.seed = static_cast<std::uint64_t>(s);
    run_into(t, options);
  }
  const double found = 100.0 * static_cast<double>(t.found) / static_cast<double>(t.true_pairs);
  const double clear = 100.0 * static_cast<double>(t.clear) / static_cast<double>(t.true_pairs);
  std::printf(
      "%-28s runs %3d  true %6lld  found %6.2f %%  unflagged %6.2f %%  wrong: unflagged %lld "
      "(%lld within 3 ms, %lld coincident), flagged %lld  (most edges between cause and effect: %d)\n",
      name.c_str(), t.runs, static_cast<long long>(t.true_pairs), found, clear,
      static_cast<long long>(t.wrong_clear), static_cast<long long>(t.wrong_clear_in_cluster),
      static_cast<long long>(t.wrong_clear_coincident), static_cast<long long>(t.wrong_flagged),
      t.most_between);
  EXPECT_LE(t.wrong_clear, bound.max_wrong_clear) << name;
  if (bound.max_wrong_clear_shifted >= 0) {
    EXPECT_LE(t.wrong_clear - t.wrong_clear_in_cluster - t.wrong_clear_coincident,
              bound.max_wrong_clear_shifted)
        << name;
  }
  EXPECT_GE(found, bound.min_found_pct) << name;
  EXPECT_GE(100.0 * static_cast<double>(t.clear - t.wrong_clear) / static_cast<double>(t.true_pairs),
            bound.min_clear_pct)
      << name;
}

const std::vector<std::vector<double>> kWheels{{0}, {0, 30}, {0, 20, 40}, {0, 90, 180, 270}};

LogOptions with_wheel(LogOptions o, const std::vector<double>& wheel) {
  o.magnets_deg = wheel;
  return o;
}
std::string wheel_name(const std::vector<double>& wheel) { return std::to_string(wheel.size()) + " magnet(s)"; }

// Measured shares of the true pairs that reach the statistics (found and not flagged) in clean logs and
// with bounces and a step, per wheel of kWheels: a complete sweep is flagged only where the spacing of
// its passes does not follow the other side's.
const std::vector<double> kCleanShare{98.5, 97.0, 90.0, 73.5};

TEST(MatcherGenerated, CleanLogsGiveExactlyTheTruePairs) {
  for (std::size_t w = 0; w < kWheels.size(); ++w)
    expect_promise("clean, " + wheel_name(kWheels[w]), with_wheel({}, kWheels[w]), 10,
                   Bound{0, 95.0, kCleanShare[w]});
}

TEST(MatcherGenerated, StallsOfUpToSixSeconds) {
  LogOptions o;
  o.interval_min_s = 0.6;  // busy steering: up to nine edges inside one stall
  o.interval_max_s = 1.5;
  o.stalls_per_minute = 3;
  for (const auto& wheel : kWheels)
    expect_promise("stalls, " + wheel_name(wheel), with_wheel(o, wheel), 10);
}

TEST(MatcherGenerated, LostEdgesOnOneSideSpuriousOnTheOther) {
  for (const bool effect_loses : {true, false}) {
    LogOptions o;
    (effect_loses ? o.effect_loss : o.cause_loss) = 0.10;
    (effect_loses ? o.cause_spurious : o.effect_spurious) = 0.05;
    // Open (docs/matcher.md): a spurious edge landing where a lost edge's partner would be is
    // indistinguishable; several magnets lose more pairs.
    const std::vector<Bound> bounds = effect_loses
                                          ? std::vector<Bound>{{0, 99.0}, {0, 97.5}, {0, 94.0}, {1, 94.0}}
                                          : std::vector<Bound>{{0, 99.0}, {2, 97.0}, {1, 94.5}, {0, 91.0}};
    for (std::size_t w = 0; w < kWheels.size(); ++w)
      expect_promise(std::string(effect_loses ? "effect lost, cause spurious, " : "cause lost, effect spurious, ") +
                         wheel_name(kWheels[w]),
                     with_wheel(o, kWheels[w]), 10, bounds[w]);
  }
}

TEST(MatcherGenerated, BouncesAndClockSteps) {
  for (const double step : {0.04, -0.04}) {
    LogOptions o;
    o.bounce_probability = 0.2;
    o.effect_step_s = step;
    for (std::size_t w = 0; w < kWheels.size(); ++w)
      expect_promise("bounces, step " + std::to_string(step) + ", " + wheel_name(kWheels[w]),
                     with_wheel(o, kWheels[w]), 6, Bound{0, 95.0, kCleanShare[w] - 0.5});
  }
}

// Stalls, lost, spurious and bouncing edges and a clock step in one log.
LogOptions everything_at_once() {
  LogOptions o;
  o.interval_min_s = 0.8;
  o.interval_max_s = 3;
  o.stalls_per_minute = 1;
  o.cause_loss = o.effect_loss = 0.03;
  o.cause_spurious = o.effect_spurious = 0.02;
  o.bounce_probability = 0.05;
  o.effect_step_s = 0.04;
  return o;
}

TEST(MatcherGenerated, EverythingAtOnce) {
  const LogOptions o = everything_at_once();
  const std::vector<Bound> bounds{{2, 98.5}, {8, 95.0}, {6, 93.5}, {1, 83.1}};  // open: docs/matcher.md
  for (std::size_t w = 0; w < kWheels.size(); ++w)
    expect_promise("all, " + wheel_name(kWheels[w]), with_wheel(o, kWheels[w]), 10, bounds[w]);
}

// One magnet, fifty runs each: everything at once (as above), and 10 % of the edges lost and 10 %
// spurious on both sides. Most wrong pairs left unflagged are coincidences (docs/matcher.md, Limits):
// no rule can flag them without flagging true pairs that look the same. The rest, chains shifted by
// one edge next to an unconfirmed jump or at a stall, are bounded by the figures measured, so that
// they can only get better.
TEST(MatcherGenerated, WhatIsLeftWithOneMagnetIsMostlyCoincidence) {
  expect_promise("all, 1 magnet, 50 runs", everything_at_once(), 50, Bound{14, 98.5, 0, 5});
  LogOptions heavy;
  heavy.cause_loss = heavy.effect_loss = 0.10;
  heavy.cause_spurious = heavy.effect_spurious = 0.10;
  expect_promise("10 % lost and spurious, 50 runs", heavy, 50, Bound{100, 98.0, 0, 12});
}

}  // namespace m2mlat::pairing::generated_test
