// Logarithm, exponential and cosine from + - * / only (core/portable_math.hpp): within a few ulp of
// the C library's, exact at the points where the value is exact.
#include "m2mlat/core/portable_math.hpp"

#include <gtest/gtest.h>

#include <cmath>

using m2mlat::core::portable_cos;
using m2mlat::core::portable_exp;
using m2mlat::core::portable_log;

TEST(PortableMath, AgreesWithTheLibrary) {
  for (double x = 1e-300; x < 1e300; x *= 1.37)
    EXPECT_NEAR(portable_log(x), std::log(x), 1e-15 * std::abs(std::log(x)) + 1e-15);
  for (double x = -700; x < 700; x += 0.731)
    EXPECT_NEAR(portable_exp(x), std::exp(x), 4e-16 * std::exp(x)) << x;
  EXPECT_EQ(portable_log(1.0), 0.0);
  EXPECT_EQ(portable_exp(0.0), 1.0);
  EXPECT_NEAR(portable_log(5e-324), std::log(5e-324), 1e-12);  // subnormal input
  EXPECT_TRUE(std::isinf(portable_log(0.0)));
  for (double x = -100; x < 100; x += 0.0137) EXPECT_NEAR(portable_cos(x), std::cos(x), 2e-16 * 100) << x;
  EXPECT_EQ(portable_cos(0.0), 1.0);
  EXPECT_NEAR(portable_cos(3.141592653589793), -1.0, 1e-15);
}
