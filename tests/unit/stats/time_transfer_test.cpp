// ADEV, MDEV, TDEV and MTIE: hand-computed values on short records, and the slopes of known noises.
#include "m2mlat/stats/time_transfer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {
namespace {

using namespace std::chrono_literals;

TEST(TimeTransfer, QuadraticPhaseHasConstantSecondDifference) {
  // x_i = i^2 ns: every second difference at n = 1 is 2 ns, so ADEV^2 = 4 / (2 tau0^2).
  const std::vector<double> x{0, 1, 4, 9, 16};
  const auto tau0 = core::Duration{1000};
  EXPECT_DOUBLE_EQ(adev(x, tau0, 1), std::sqrt(2.0) / 1000);
  // n = 2: d = x4 - 2 x2 + x0 = 8, one term: ADEV^2 = 64 / (2 * 2000^2).
  EXPECT_DOUBLE_EQ(adev(x, tau0, 2), std::sqrt(32.0) / 2000);
  // MDEV at n = 1 equals ADEV; at n = 1 with N = 5 there are 3 inner sums of one term each.
  EXPECT_DOUBLE_EQ(mdev(x, tau0, 1), adev(x, tau0, 1));
  EXPECT_DOUBLE_EQ(tdev(x, tau0, 1), 1000 / std::sqrt(3.0) * mdev(x, tau0, 1));
}

TEST(TimeTransfer, ModifiedAllanByHand) {
  // N = 6, n = 2: second differences d_i = x_{i+4} - 2 x_{i+2} + x_i for i = 0, 1;
  // one inner sum (j = 0): d_0 + d_1; MVAR = (d_0 + d_1)^2 / (2 tau^2 n^2 * 1).
  const std::vector<double> x{0, 3, 1, 5, 2, 7};
  const double d0 = 2 - 2 * 1 + 0, d1 = 7 - 2 * 5 + 3;
  const double tau = 2 * 10.0;
  EXPECT_DOUBLE_EQ(mdev(x, core::Duration{10}, 2), std::sqrt((d0 + d1) * (d0 + d1) / (2 * tau * tau * 4)));
  // Too short records give NaN.
  EXPECT_TRUE(std::isnan(mdev(x, core::Duration{10}, 3)));
  EXPECT_TRUE(std::isnan(adev(x, core::Duration{10}, 3)));
}

TEST(TimeTransfer, ConstantFrequencyOffsetHasNoInstability) {
  std::vector<double> x;
  for (int i = 0; i < 50; ++i) x.push_back(100.0 + 7.5 * i);
  for (std::size_t n : {1u, 2u, 4u, 8u}) {
    EXPECT_NEAR(adev(x, 1s, n), 0, 1e-15);
    EXPECT_NEAR(tdev(x, 1s, n), 0, 1e-9);
  }
  // But the time error grows: MTIE over n intervals is 7.5 n ns.
  EXPECT_DOUBLE_EQ(mtie(x, 4), 30.0);
}

TEST(TimeTransfer, MtieByHand) {
  const std::vector<double> x{0, 3, 1, 5, 2};
  EXPECT_DOUBLE_EQ(mtie(x, 1), 4);  // 1 -> 5
  EXPECT_DOUBLE_EQ(mtie(x, 2), 4);  // windows {0,3,1} 3, {3,1,5} 4, {1,5,2} 4
  EXPECT_DOUBLE_EQ(mtie(x, 4), 5);  // the whole record
  EXPECT_TRUE(std::isnan(mtie(x, 5)));
}

TEST(TimeTransfer, BadArgumentsAreUsageErrors) {
  const std::vector<double> x{0, 1, 2};
  EXPECT_THROW(adev(x, 1s, 0), core::Error);
  EXPECT_THROW(mdev(x, core::Duration{0}, 1), core::Error);
  EXPECT_THROW(mtie(x, 0), core::Error);
}

TEST(TimeTransfer, OctaveFactors) {
  EXPECT_EQ(octave_factors(2), std::vector<std::size_t>{});
  EXPECT_EQ(octave_factors(3), std::vector<std::size_t>{1});
  EXPECT_EQ(octave_factors(17), (std::vector<std::size_t>{1, 2, 4, 8}));
  EXPECT_EQ(octave_factors(1000, 3), (std::vector<std::size_t>{1, 2, 4}));
}

// log-log slope between two factors.
double slope(double a, double b, double n_a, double n_b) { return std::log(b / a) / std::log(n_b / n_a); }

TEST(TimeTransfer, WhitePhaseNoiseSlopes) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> noise(0.0, 100.0);  // sd 100 ns
  std::vector<double> x(200'000);
  for (auto& v : x) v = noise(rng);
  const auto tau0 = 500ms;
  // TDEV(tau0) is the sd of the phase; ADEV(tau0) = sqrt(3) sd / tau0.
  EXPECT_NEAR(tdev(x, tau0, 1), 100.0, 2.0);
  EXPECT_NEAR(adev(x, tau0, 1) * 500e6, std::sqrt(3.0) * 100.0, 3.0);
  EXPECT_NEAR(slope(adev(x, tau0, 4), adev(x, tau0, 64), 4, 64), -1.0, 0.05);
  EXPECT_NEAR(slope(mdev(x, tau0, 4), mdev(x, tau0, 64), 4, 64), -1.5, 0.07);
  EXPECT_NEAR(slope(tdev(x, tau0, 4), tdev(x, tau0, 64), 4, 64), -0.5, 0.07);
  // MTIE of white noise is about the full spread and grows only slowly.
  EXPECT_GT(mtie(x, 1), 400.0);
  EXPECT_GE(mtie(x, 16), mtie(x, 1));
}

TEST(TimeTransfer, RandomWalkPhaseSlopes) {
  // White frequency noise: the phase is a random walk.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> step(0.0, 10.0);
  std::vector<double> x(200'000);
  double phase = 0;
  for (auto& v : x) v = phase += step(rng);
  const auto tau0 = 1s;
  EXPECT_NEAR(slope(adev(x, tau0, 4), adev(x, tau0, 256), 4, 256), -0.5, 0.07);
  EXPECT_NEAR(slope(tdev(x, tau0, 4), tdev(x, tau0, 256), 4, 256), 0.5, 0.07);
}

TEST(TimeTransfer, StabilityTableMatchesTheSingleEstimators) {
  std::vector<double> x;
  for (int i = 0; i < 40; ++i) x.push_back(std::sin(i * 0.7) * 50 + i);
  const auto factors = octave_factors(x.size());
  const auto table = stability(x, 2s, factors);
  ASSERT_EQ(table.size(), factors.size());
  for (const auto& p : table) {
    EXPECT_DOUBLE_EQ(p.tau_s, 2.0 * static_cast<double>(p.n));
    EXPECT_DOUBLE_EQ(p.adev, adev(x, 2s, p.n));
    EXPECT_EQ(p.adev_terms, x.size() - 2 * p.n);
    if (3 * p.n <= x.size())
      EXPECT_DOUBLE_EQ(p.tdev_ns, tdev(x, 2s, p.n));
    else
      EXPECT_TRUE(std::isnan(p.tdev_ns));
  }
}

}  // namespace
}  // namespace m2mlat::stats
