// Whole-text numbers: what is a number, what is refused, and that a refused text changes nothing.
#include "m2mlat/core/number.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace m2mlat::core {
namespace {

TEST(ParseInteger, TakesTheWholeTextOnly) {
  std::int64_t v = 7;
  EXPECT_TRUE(parse_integer("-1762872545550296135", v));
  EXPECT_EQ(v, -1762872545550296135);
  EXPECT_TRUE(parse_integer("9223372036854775807", v));
  EXPECT_EQ(v, std::numeric_limits<std::int64_t>::max());
  for (const char* bad : {"", "12x", " 12", "12 ", "+12", "1.5", "0x10", "-", "9223372036854775808"}) {
    v = 7;
    EXPECT_FALSE(parse_integer(bad, v)) << bad;
    EXPECT_EQ(v, 7) << bad;
  }
}

TEST(ParseInteger, UnsignedRefusesASignAndOtherBasesWork) {
  std::uint64_t u = 0;
  EXPECT_TRUE(parse_integer("18446744073709551615", u));
  EXPECT_EQ(u, std::numeric_limits<std::uint64_t>::max());
  EXPECT_FALSE(parse_integer("-0", u));
  EXPECT_FALSE(parse_integer("-1", u));
  std::uint32_t small = 0;
  EXPECT_FALSE(parse_integer("4294967296", small));
  std::int64_t hex = 0;
  EXPECT_TRUE(parse_integer("7F000001", hex, 16));
  EXPECT_EQ(hex, 0x7F000001);
  int oct = 0;
  EXPECT_TRUE(parse_integer("377", oct, 8));
  EXPECT_EQ(oct, 255);
  EXPECT_FALSE(parse_integer("378", oct, 8));
}

TEST(ParseDouble, OneOptionalSignAndTheWholeText) {
  double d = 0;
  EXPECT_TRUE(parse_double("+0.020", d));
  EXPECT_DOUBLE_EQ(d, 0.020);
  EXPECT_TRUE(parse_double("-2.5e-3", d));
  EXPECT_DOUBLE_EQ(d, -2.5e-3);
  EXPECT_TRUE(parse_double("inf", d));
  EXPECT_TRUE(std::isinf(d));
  for (const char* bad : {"", "+", "0.02x", " 1", "1 ", "+-1", "++1", "-+1", "1,5"}) {
    d = 3;
    EXPECT_FALSE(parse_double(bad, d)) << bad;
    EXPECT_EQ(d, 3) << bad;
  }
}

}  // namespace
}  // namespace m2mlat::core
