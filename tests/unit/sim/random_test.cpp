// The simulator's random numbers: exact sequences (cross-checked against an independent
// implementation of splitmix64 and xoshiro256**), and the shape of each transform.
#include "m2mlat/sim/random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "m2mlat/sim/distribution.hpp"

using namespace m2mlat::sim;
using namespace std::chrono_literals;

TEST(Random, SplitmixMatchesPublishedValue) {
  std::uint64_t state = 0;
  EXPECT_EQ(m2mlat::core::splitmix64(state),
            0xe220a8397b1dcdafULL);  // Steele, Lea and Flood's generator from state 0
  EXPECT_EQ(m2mlat::core::splitmix64(state), 0x6e789e6aa1b965f4ULL);
}

TEST(Random, StreamsAreExactAndSeparate) {
  // Values from a separate Python implementation of the seeding and xoshiro256**.
  Rng a(1, 2);
  EXPECT_EQ(a.next(), 0x5f147c977b052899ULL);
  EXPECT_EQ(a.next(), 0x3beb7d2db94e1f5dULL);
  EXPECT_EQ(a.next(), 0x2263ee6c6d422ac7ULL);
  Rng b(0xdeadbeef, 7);
  EXPECT_EQ(b.next(), 0x3f78e62780bb7021ULL);
  Rng c(1, 2);
  EXPECT_EQ(c.uniform(), 0.3714063520265155);  // the top 53 bits of the first output, / 2^53
  Rng d(1, 3);
  EXPECT_NE(d.next(), 0x5f147c977b052899ULL);
}

TEST(Random, UniformAndIntegerRanges) {
  Rng rng(5, 1);
  double sum = 0;
  std::vector<int> counts(7, 0);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    const auto k = rng.uniform_int(-3, 3);
    ASSERT_GE(k, -3);
    ASSERT_LE(k, 3);
    ++counts[static_cast<std::size_t>(k + 3)];
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  for (int count : counts) EXPECT_NEAR(count, n / 7.0, 5 * std::sqrt(n / 7.0));
}

TEST(Random, NormalHasUnitVarianceAndTails) {
  Rng rng(9, 1);
  const int n = 1'000'000;
  double sum = 0, sum2 = 0;
  int beyond3 = 0, beyond1 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.normal();
    sum += x;
    sum2 += x * x;
    beyond3 += std::abs(x) > 3 ? 1 : 0;
    beyond1 += std::abs(x) > 1 ? 1 : 0;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.005);
  EXPECT_NEAR(sum2 / n, 1.0, 0.005);
  EXPECT_NEAR(beyond1 / static_cast<double>(n), 0.317311, 0.002);    // 2 * (1 - Phi(1))
  EXPECT_NEAR(beyond3 / static_cast<double>(n), 0.0026998, 0.0003);  // 2 * (1 - Phi(3)): the tail works
}

TEST(Random, ExponentialHasUnitMeanAndTail) {
  Rng rng(11, 1);
  const int n = 1'000'000;
  double sum = 0;
  int beyond5 = 0, beyond9 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.exponential();
    ASSERT_GE(x, 0.0);
    sum += x;
    beyond5 += x > 5 ? 1 : 0;
    beyond9 += x > 9 ? 1 : 0;  // beyond the ziggurat's base at 7.7
  }
  EXPECT_NEAR(sum / n, 1.0, 0.005);
  EXPECT_NEAR(beyond5 / static_cast<double>(n), std::exp(-5.0), 0.0003);
  EXPECT_NEAR(beyond9 / static_cast<double>(n), std::exp(-9.0), 0.00004);
}

TEST(Distribution, ShapesHaveTheirMedians) {
  Rng rng(3, 1);
  auto median_of = [&](const DurationDist& dist) {
    std::vector<std::int64_t> v;
    for (int i = 0; i < 20001; ++i) v.push_back(sample(dist, rng).count());
    std::nth_element(v.begin(), v.begin() + 10000, v.end());
    return static_cast<double>(v[10000]);
  };
  EXPECT_EQ(sample(constant(5ms), rng), 5ms);
  EXPECT_NEAR(median_of(uniform(10ms, 20ms)), 20e6, 0.3e6);
  EXPECT_NEAR(median_of(normal(100ms, 10ms, 0ms)), 100e6, 0.3e6);
  EXPECT_NEAR(median_of(exponential(1ms, 10ms)), 1e6 + 10e6 * std::log(2.0), 0.3e6);
  EXPECT_NEAR(median_of(lognormal(3ms, 10ms, 0.8)), 13e6, 0.3e6);
  // Clamping.
  DurationDist clamped = normal(0ms, 10ms, 0ms);
  clamped.max = 5ms;
  for (int i = 0; i < 1000; ++i) {
    const auto d = sample(clamped, rng);
    EXPECT_GE(d, 0ms);
    EXPECT_LE(d, 5ms);
  }
}
