#include "m2mlat/pairing/matcher.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/pairing/refractory.hpp"

using namespace m2mlat;
using pairing::match;
using pairing::UnmatchedReason;

namespace {
constexpr std::int64_t kMs = 1'000'000;

std::vector<std::pair<std::int64_t, std::int64_t>> index_pairs(const pairing::MatchResult& r) {
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for (const auto& p : r.pairs) out.emplace_back(p.cause_index, p.effect_index);
  return out;
}
using IndexPairs = std::vector<std::pair<std::int64_t, std::int64_t>>;
}  // namespace

TEST(Refractory, KeepsFirstEdgeOfEachBurst) {
  const std::vector<std::int64_t> t{0, 2 * kMs, 9 * kMs, 12 * kMs, 30 * kMs};
  const auto r = pairing::refractory_filter(t, std::chrono::milliseconds(10));
  EXPECT_EQ(r.kept, (std::vector<std::int64_t>{0, 3, 4}));
  EXPECT_EQ(r.bounces, (std::vector<std::int64_t>{1, 2}));
}

TEST(Refractory, BouncesAloneAndKeptIndex) {
  // Bounces at the start, in a run, and at the end; a period of 0 keeps everything.
  const std::vector<std::int64_t> t{0,        1 * kMs,  2 * kMs,  20 * kMs, 40 * kMs,
                                    45 * kMs, 46 * kMs, 80 * kMs, 81 * kMs};
  const auto bounces = pairing::refractory_bounces(t, std::chrono::milliseconds(10));
  EXPECT_EQ(bounces, (std::vector<std::int64_t>{1, 2, 5, 6, 8}));
  EXPECT_EQ(bounces, pairing::refractory_filter(t, std::chrono::milliseconds(10)).bounces);
  EXPECT_TRUE(pairing::refractory_bounces(t, std::chrono::milliseconds(0)).empty());
  const std::vector<std::int64_t> kept{0, 3, 4, 7};
  pairing::KeptIndex all(bounces);
  for (std::size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(all(k), kept[k]) << k;
  pairing::KeptIndex skipping(bounces);  // positions may be skipped, as for the unmatched ones
  EXPECT_EQ(skipping(1), 3);
  EXPECT_EQ(skipping(3), 7);
  pairing::KeptIndex none({});
  EXPECT_EQ(none(5), 5);
}

TEST(Matcher, SingleMagnetClean) {
  const std::vector<std::int64_t> c{0, 2500 * kMs, 5100 * kMs};
  const std::vector<std::int64_t> e{800 * kMs, 3350 * kMs, 5850 * kMs};
  const auto r = match(c, e, core::Clock::realtime);
  EXPECT_EQ(index_pairs(r), (IndexPairs{{0, 0}, {1, 1}, {2, 2}}));
  EXPECT_TRUE(r.unmatched.empty());
  EXPECT_EQ(pairing::PairTimes({c, e}).latency(r.pairs[1]).count(), 850 * kMs);
}

TEST(Matcher, MultiMagnetBurstWithMissedEffectEdge) {
  // Three magnets 30 ms apart on the operator wheel; the vehicle wheel turns a bit slower (40 ms
  // spacing) 800 ms later and its middle edge is missed. A nearest-neighbour or first-after rule
  // pairs cause 1 with effect 1 (the third magnet); the right answer leaves cause 1 alone.
  const std::vector<std::int64_t> c{0, 30 * kMs, 60 * kMs, 3000 * kMs, 3030 * kMs, 3060 * kMs};
  const std::vector<std::int64_t> e{800 * kMs, 880 * kMs, 3790 * kMs, 3830 * kMs, 3870 * kMs};
  const auto r = match(c, e, core::Clock::realtime);
  EXPECT_EQ(index_pairs(r), (IndexPairs{{0, 0}, {2, 1}, {3, 2}, {4, 3}, {5, 4}}));
  ASSERT_EQ(r.unmatched.size(), 1u);
  EXPECT_EQ(r.unmatched[0].side, pairing::Side::cause);
  EXPECT_EQ(r.unmatched[0].index, 1);
  EXPECT_EQ(r.unmatched[0].reason, UnmatchedReason::outmatched);
}

TEST(Matcher, MissingEffectDoesNotShiftLaterPairs) {
  // Manoeuvres 2 s apart, latency ~0.8 s: the first effect is missing and a spurious effect follows.
  // Order-preserving cardinality alone would pair cause 0 with effect 0 (2.8 s) and cause 1 with the
  // spurious edge; the local latency says cause 1 -> effect 0.
  std::vector<std::int64_t> c, e;
  for (int k = 0; k < 30; ++k) {
    c.push_back(k * 2000 * kMs);
    if (k != 10) e.push_back(k * 2000 * kMs + 800 * kMs + (k % 3) * 20 * kMs);
  }
  e.push_back(11 * 2000 * kMs + 1500 * kMs);  // spurious
  std::sort(e.begin(), e.end());
  const auto r = match(c, e, core::Clock::realtime);
  ASSERT_EQ(r.pairs.size(), 29u);
  const pairing::PairTimes times{c, e};
  for (const auto& p : r.pairs) {
    EXPECT_GE(times.latency(p).count(), 800 * kMs);
    EXPECT_LE(times.latency(p).count(), 840 * kMs);
  }
  std::size_t reasons_cause = 0, reasons_effect = 0;
  for (const auto& u : r.unmatched) (u.side == pairing::Side::cause ? reasons_cause : reasons_effect)++;
  EXPECT_EQ(reasons_cause, 1u);
  EXPECT_EQ(reasons_effect, 1u);
}

namespace {
// A steady run: a cause every 2 s, its effect 800, 820 or 840 ms later (an acceptance of 150 ms).
void steady(std::vector<std::int64_t>& c, std::vector<std::int64_t>& e, int from, int to) {
  for (int k = from; k < to; ++k) {
    c.push_back(k * 2000 * kMs);
    e.push_back(k * 2000 * kMs + 800 * kMs + (k % 3) * 20 * kMs);
  }
}
}  // namespace

TEST(Matcher, AStallIsConfirmedWhenItsQueueDrains) {
  // The link stalls from 39.5 s to 45.2 s: the commands of the causes at 40, 42 and 44 s leave
  // together and their effects come 30 ms apart, 6.0, 4.03 and 2.06 s after their causes. Every edge
  // is paired and the run lies above the reference: a real jump, no flag. The same run whose last
  // effect keeps its cause's spacing (3.9 s after it: a spurious edge after the drain in the place of
  // an effect that was lost) is no queue draining: its pairs are flagged as a jump.
  for (const bool drains : {true, false}) {
    std::vector<std::int64_t> c, e;
    steady(c, e, 0, 20);
    for (const std::int64_t k : {0, 1, 2}) c.push_back((40'000 + 2'000 * k) * kMs);
    for (const std::int64_t at : {46'000, 46'030, drains ? 46'060 : 47'900}) e.push_back(at * kMs);
    steady(c, e, 24, 40);
    const auto r = match(c, e, core::Clock::realtime);
    ASSERT_EQ(r.pairs.size(), c.size()) << drains;
    for (const auto& p : r.pairs) {
      EXPECT_EQ(p.cause_index, p.effect_index);
      const bool stalled = p.cause_index >= 20 && p.cause_index < 23;
      EXPECT_EQ(p.flags, stalled && !drains ? pairing::kPairJump : 0u) << p.cause_index << " " << drains;
    }
  }
}

TEST(Matcher, TheNeighbourOfAnUnconfirmedJumpThatFitsItsEdgeIsFlagged) {
  // Cause 10's effect is lost; cause 10 takes cause 11's effect (2.82 s: a jump, unconfirmed) and
  // cause 11 a spurious edge 930 ms after it (typical). Cause 11 fits its true effect better: its
  // pair is flagged as competing, so that no wrong pair reaches the statistics. A real outlier (cause
  // 10's effect 1.3 s late) leaves its neighbours alone: no other edge fits them.
  for (const bool lost : {true, false}) {
    std::vector<std::int64_t> c, e;
    steady(c, e, 0, 30);
    if (lost) {
      e[10] = 22'930 * kMs;  // the spurious edge; cause 11's effect stays at 22.82 s
      std::sort(e.begin(), e.end());
    } else {
      e[10] = 21'300 * kMs;
    }
    const auto r = match(c, e, core::Clock::realtime);
    ASSERT_EQ(r.pairs.size(), 30u) << lost;
    for (const auto& p : r.pairs) {
      const std::uint32_t expected = p.cause_index == 10           ? pairing::kPairJump
                                     : lost && p.cause_index == 11 ? pairing::kPairCompeting
                                                                   : 0u;
      EXPECT_EQ(p.flags, expected) << p.cause_index << " " << lost;
    }
  }
}

TEST(Matcher, BouncesAreReportedAndIgnored) {
  const std::vector<std::int64_t> c{0, 1 * kMs, 3 * kMs, 2000 * kMs};
  const std::vector<std::int64_t> e{750 * kMs, 752 * kMs, 2760 * kMs};
  const auto r = match(c, e, core::Clock::realtime);
  EXPECT_EQ(index_pairs(r), (IndexPairs{{0, 0}, {3, 2}}));
  ASSERT_EQ(r.unmatched.size(), 3u);
  for (const auto& u : r.unmatched) EXPECT_EQ(u.reason, UnmatchedReason::bounce);
  // The first pair's edges were followed by bounces for 3 ms (cause) and 2 ms (effect): the pass's
  // edge may be a later one of either cluster, so its latency is known to within 5 ms; 3 ms on one
  // side is not yet "bounced" (kBounceSpanLimit).
  EXPECT_EQ(r.pairs[0].bounce_span_ns, 5 * kMs);
  EXPECT_EQ(r.pairs[0].flags & pairing::kPairBounced, 0u);
  EXPECT_EQ(r.pairs[1].bounce_span_ns, 0);
}

TEST(Matcher, InPlaceGivesTheSameResultAndPutsTheColumnsBack) {
  // Bounces on both sides (a run of them, one after the last kept edge), so that the kept edges move
  // to the front of the columns while the matcher runs.
  std::vector<std::int64_t> c{0, 2500 * kMs, 2502 * kMs, 2505 * kMs, 5100 * kMs, 7600 * kMs, 7601 * kMs};
  std::vector<std::int64_t> e{800 * kMs,  803 * kMs,  3350 * kMs, 5850 * kMs,
                              5851 * kMs, 8400 * kMs, 8409 * kMs};
  const auto c0 = c, e0 = e;
  const auto expected = match(c0, e0, core::Clock::realtime);
  const auto r = pairing::match_in_place(c, e, core::Clock::realtime);
  EXPECT_EQ(c, c0);
  EXPECT_EQ(e, e0);
  EXPECT_EQ(index_pairs(r), (IndexPairs{{0, 0}, {1, 2}, {4, 3}, {5, 5}}));
  EXPECT_EQ(r.pairs, expected.pairs);
  EXPECT_EQ(r.unmatched, expected.unmatched);
  ASSERT_EQ(r.unmatched.size(), 6u);
  for (const auto& u : r.unmatched) EXPECT_EQ(u.reason, UnmatchedReason::bounce);
}

TEST(Matcher, NoCandidateReason) {
  // Farther apart than the default window (10 s) either way.
  const std::vector<std::int64_t> c{0, 15'000 * kMs};
  const std::vector<std::int64_t> e{800 * kMs, 30'000 * kMs};
  const auto r = match(c, e, core::Clock::realtime);
  EXPECT_EQ(index_pairs(r), (IndexPairs{{0, 0}}));
  ASSERT_EQ(r.unmatched.size(), 2u);
  EXPECT_EQ(r.unmatched[0].reason, UnmatchedReason::no_candidate);
  EXPECT_EQ(r.unmatched[1].reason, UnmatchedReason::no_candidate);
}

TEST(Matcher, EmptyAndInvalidInput) {
  EXPECT_TRUE(match(std::span<const std::int64_t>{}, std::span<const std::int64_t>{}, core::Clock::realtime)
                  .pairs.empty());
  const std::vector<std::int64_t> unsorted{5, 3};
  const std::vector<std::int64_t> sorted{1, 2};
  EXPECT_THROW(match(unsorted, sorted, core::Clock::realtime), core::Error);
  pairing::MatchOptions bad;
  bad.max_latency = bad.min_latency;
  EXPECT_THROW(match(sorted, sorted, core::Clock::realtime, bad), core::Error);
}

TEST(Matcher, EventsOfDifferentClocksAreRefused) {
  std::vector<core::Event> c(1), e(1);
  c[0].time = core::TimePoint::from_ns(core::Clock::realtime, 0);
  e[0].time = core::TimePoint::from_ns(core::Clock::monotonic, 800 * kMs);
  EXPECT_THROW(match(c, e), core::Error);
  e[0].time = core::TimePoint::from_ns(core::Clock::realtime, 800 * kMs);
  EXPECT_EQ(match(c, e).pairs.size(), 1u);
}
