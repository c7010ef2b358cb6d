// The lattice's forward-backward and Viterbi against the oracle's enumeration of every alignment.
#include "m2mlat/pairing/alignment_lattice.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "alignment_oracle.hpp"

namespace m2mlat::pairing::alignment_lattice_test {

constexpr std::int64_t kMs = 1'000'000;

struct Case {
  std::vector<std::int64_t> cause, effect;
  AlignmentModel model;
};

// A few edges a side: bursts of passes tens of ms apart, a latency near 0.8 s, edges lost and
// spurious ones added; the model's parameters drawn too.
Case random_case(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Case c;
  const int causes = 1 + static_cast<int>(rng() % 6);
  std::int64_t t = 1'000'000 * kMs;
  const double latency = 0.5 + u(rng);
  for (int i = 0; i < causes; ++i) {
    t += u(rng) < 0.6 ? static_cast<std::int64_t>((30 + 80 * u(rng)) * kMs) : static_cast<std::int64_t>((500 + 1500 * u(rng)) * kMs);
    c.cause.push_back(t);
    if (u(rng) < 0.8) c.effect.push_back(t + static_cast<std::int64_t>((latency + 0.05 * u(rng)) * 1e9));
  }
  const int spurious = static_cast<int>(rng() % 3);
  for (int s = 0; s < spurious; ++s) c.effect.push_back(c.cause.front() + static_cast<std::int64_t>(u(rng) * 4e9));
  std::sort(c.effect.begin(), c.effect.end());
  if (c.effect.size() > 7) c.effect.resize(7);
  auto& m = c.model;
  m.cause_loss = 0.01 + 0.3 * u(rng);
  m.unmatched_per_s = 0.01 + 0.5 * u(rng);
  m.reset = 0.001 + 0.2 * u(rng);
  m.mean_s = latency + 0.1 * (u(rng) - 0.5);
  m.spread_s = 0.02 + 0.2 * u(rng);
  m.tau_s = 1 + 30 * u(rng);
  m.stretch = 0.7 + 0.8 * u(rng);
  m.stretch_sd = 0.05 + 0.3 * u(rng);
  m.sweep = 0.05 + 0.9 * u(rng);
  m.sweep_sd = 0.01 + 0.2 * u(rng);
  m.jitter_s = 0.001 + 0.01 * u(rng);
  m.max_skip = rng() % 3;
  m.min_latency_s = 0;
  m.max_latency_s = 2 + 2 * u(rng);
  return c;
}

TEST(AlignmentLattice, EveryPosteriorAndTheBestAlignmentAreTheOraclesOnSmallInputs) {
  int ties = 0;
  for (std::uint64_t seed = 1; seed <= 3000; ++seed) {
    const auto c = random_case(seed);
    const AlignmentLattice lattice(c.cause, c.effect, c.model);
    const auto want = oracle::enumerate(c.cause, c.effect, c.model);
    ASSERT_NEAR(lattice.log_evidence(), want.log_z, 1e-9) << seed;
    for (std::size_t i = 0; i < c.cause.size(); ++i)
      for (std::size_t j = 0; j < c.effect.size(); ++j) {
        const auto it = want.posterior.find({i, j});
        ASSERT_NEAR(lattice.posterior(i, j), it == want.posterior.end() ? 0.0 : it->second, 1e-9)
            << "seed " << seed << " pair " << i << "," << j;
      }
    // The best alignment: the oracle's, or one of equal score (a tie: both fresh draws).
    EXPECT_NEAR(lattice.best().log_score, want.best_score, 1e-9) << seed;
    EXPECT_NEAR(oracle::log_score(c.cause, c.effect, c.model, lattice.best().pairs, true), want.best_score, 1e-9) << seed;
    if (lattice.best().pairs != want.best) ++ties;
  }
  EXPECT_LE(ties, 50);
}

TEST(AlignmentLattice, NoEdgesIsOneEmptyAlignment) {
  const AlignmentLattice lattice({}, {}, AlignmentModel{});
  EXPECT_TRUE(lattice.best().pairs.empty());
  EXPECT_NEAR(lattice.log_evidence(), 0.0, 1e-12);
}

TEST(AlignmentLattice, AClearRunIsPairedWithCertainty) {
  std::vector<std::int64_t> cause, effect;
  for (int i = 0; i < 50; ++i) {
    cause.push_back(1'000'000 * kMs + i * 2'000 * kMs);
    effect.push_back(cause.back() + 800 * kMs + (i % 5) * kMs);
  }
  AlignmentModel m;
  m.spread_s = 0.01;
  const AlignmentLattice lattice(cause, effect, m);
  ASSERT_EQ(lattice.best().pairs.size(), 50u);
  for (std::size_t k = 0; k < 50; ++k) {
    EXPECT_EQ(lattice.best().pairs[k], std::make_pair(k, k));
    EXPECT_GT(lattice.best().probability[k], 0.999);
  }
}

TEST(AlignmentLattice, CausesOnOneStampGiveFiniteProbabilities) {
  const std::vector<std::int64_t> cause{1'000 * kMs, 1'000 * kMs, 1'000 * kMs, 3'000 * kMs};
  const std::vector<std::int64_t> effect{1'800 * kMs, 1'850 * kMs, 3'800 * kMs};
  const AlignmentLattice lattice(cause, effect, AlignmentModel{});
  EXPECT_TRUE(std::isfinite(lattice.log_evidence()));
  for (const double p : lattice.best().probability) EXPECT_TRUE(p >= 0 && p <= 1 + 1e-12);
  const auto want = oracle::enumerate(cause, effect, AlignmentModel{});
  EXPECT_NEAR(lattice.log_evidence(), want.log_z, 1e-9);
}

}  // namespace m2mlat::pairing::alignment_lattice_test
