// Pulse pairing: the same edge on two boards, with missing and extra edges and offsets near half a
// period.
#include "m2mlat/pairing/pulse_pairing.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "m2mlat/core/error.hpp"

namespace m2mlat::pairing {
namespace {

using namespace std::chrono_literals;
constexpr std::int64_t kPeriod = 500'000'000;  // 500 ms
constexpr std::int64_t kStart = 1'762'872'545'000'000'000;

std::vector<std::int64_t> pulses(int count, std::int64_t offset) {
  std::vector<std::int64_t> t;
  for (int i = 0; i < count; ++i) t.push_back(kStart + i * kPeriod + offset);
  return t;
}

TEST(PulsePairing, EveryEdgeOnBothBoards) {
  const auto a = pulses(10, 0), b = pulses(10, 312'256);
  const auto r = pair_pulses(a, b);
  EXPECT_EQ(r.period.count(), kPeriod);  // estimated from A
  ASSERT_EQ(r.pairs.size(), 10u);
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    EXPECT_EQ(r.pairs[i].a_index, i);
    EXPECT_EQ(r.pairs[i].b_index, i);
    EXPECT_EQ(r.pairs[i].offset_ns(), 312'256);
  }
  EXPECT_TRUE(r.unmatched_a.empty());
  EXPECT_TRUE(r.unmatched_b.empty());
}

TEST(PulsePairing, MissingEdgesLeaveTheirPartnersUnmatched) {
  auto a = pulses(10, 0), b = pulses(10, -40'000);
  a.erase(a.begin() + 3);  // A missed pulse 3
  b.erase(b.begin() + 7);  // B missed pulse 7
  const auto r = pair_pulses(a, b, {core::Duration{kPeriod}, {}});
  EXPECT_EQ(r.pairs.size(), 8u);
  for (const auto& p : r.pairs) EXPECT_EQ(p.offset_ns(), -40'000);
  EXPECT_EQ(r.unmatched_b, std::vector<std::size_t>{3});  // B's pulse 3
  EXPECT_EQ(r.unmatched_a, std::vector<std::size_t>{6});  // A's pulse 7 (index 6 after the erase)
}

TEST(PulsePairing, ExtraEdgesLoseToTheRealOne) {
  auto a = pulses(6, 0), b = pulses(6, 1'000'000);
  b.push_back(kStart + 2 * kPeriod + 30'000'000);  // a glitch 30 ms after pulse 2 on B
  a.push_back(kStart + 4 * kPeriod - 90'000'000);  // and one on A 90 ms before pulse 4
  const auto r = pair_pulses(a, b, {core::Duration{kPeriod}, {}});
  EXPECT_EQ(r.pairs.size(), 6u);
  for (const auto& p : r.pairs) EXPECT_EQ(p.offset_ns(), 1'000'000);
  EXPECT_EQ(r.unmatched_b, std::vector<std::size_t>{6});
  EXPECT_EQ(r.unmatched_a, std::vector<std::size_t>{6});
}

TEST(PulsePairing, HalfAPeriodApartIsNoPair) {
  const auto a = pulses(4, 0);
  // Exactly half a period later: equally near two of A's pulses, so neither side is matched.
  const auto b = pulses(4, kPeriod / 2);
  const auto r = pair_pulses(a, b, {core::Duration{kPeriod}, {}});
  EXPECT_TRUE(r.pairs.empty());
  EXPECT_EQ(r.unmatched_a.size(), 4u);
  EXPECT_EQ(r.unmatched_b.size(), 4u);
  // With the offset known in advance the same edges pair.
  const auto known = pair_pulses(a, b, {core::Duration{kPeriod}, core::Duration{kPeriod / 2}});
  EXPECT_EQ(known.pairs.size(), 4u);
  for (const auto& p : known.pairs) EXPECT_EQ(p.offset_ns(), kPeriod / 2);
}

TEST(PulsePairing, UnsortedInputKeepsItsPositions) {
  const std::vector<std::int64_t> a{kStart + 2 * kPeriod, kStart, kStart + kPeriod};
  const std::vector<std::int64_t> b{kStart + 5, kStart + kPeriod + 5, kStart + 2 * kPeriod + 5};
  const auto r = pair_pulses(a, b, {core::Duration{kPeriod}, {}});
  ASSERT_EQ(r.pairs.size(), 3u);
  EXPECT_EQ(r.pairs[0].a_index, 1u);
  EXPECT_EQ(r.pairs[0].b_index, 0u);
  EXPECT_EQ(r.pairs[2].a_index, 0u);
  EXPECT_EQ(r.pairs[2].b_index, 2u);
}

TEST(PulsePairing, RandomLossesAndGlitchesAreOneToOne) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> jitter(0, 200'000);  // 0.2 ms
  for (int round = 0; round < 20; ++round) {
    std::vector<std::int64_t> a, b;
    std::set<std::pair<std::int64_t, std::int64_t>> truth;
    for (int i = 0; i < 500; ++i) {
      const std::int64_t ta = kStart + i * kPeriod;
      const std::int64_t tb = ta + 800'000 + static_cast<std::int64_t>(jitter(rng));
      const bool ka = u(rng) > 0.05, kb = u(rng) > 0.05;
      if (ka) a.push_back(ta);
      if (kb) b.push_back(tb);
      if (ka && kb) truth.insert({ta, tb});
      if (u(rng) < 0.02) b.push_back(ta + static_cast<std::int64_t>(u(rng) * kPeriod));
    }
    const auto r = pair_pulses(a, b, {core::Duration{kPeriod}, {}});
    std::set<std::size_t> used_a, used_b;
    std::size_t right = 0;
    for (const auto& p : r.pairs) {
      EXPECT_TRUE(used_a.insert(p.a_index).second);
      EXPECT_TRUE(used_b.insert(p.b_index).second);
      right += truth.count({p.a_ns, p.b_ns});
    }
    EXPECT_EQ(r.pairs.size() + r.unmatched_a.size(), a.size());
    EXPECT_EQ(r.pairs.size() + r.unmatched_b.size(), b.size());
    // A glitch can only win when it lands nearer than the true edge (within ~1 ms of a pulse).
    EXPECT_GE(right, truth.size() - 3);
  }
}

TEST(PulsePairing, PeriodErrors) {
  const std::vector<std::int64_t> one{kStart};
  EXPECT_THROW(pair_pulses(one, one), core::Error);
  EXPECT_THROW(pair_pulses(one, one, {core::Duration{-1}, {}}), core::Error);
  EXPECT_EQ(pair_pulses(one, one, {core::Duration{kPeriod}, {}}).pairs.size(), 1u);
  EXPECT_EQ(median_interval(std::vector<std::int64_t>{5, 1, 3, 9}).count(), 2);
}

}  // namespace
}  // namespace m2mlat::pairing
