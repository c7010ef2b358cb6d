// Whole-text numbers: what is a number, what is refused, and that a refused text changes nothing.
#include "m2mlat/core/number.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>

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

// The 64-bit decimal fast path (8 digits at a time) against std::from_chars, which it replaces for
// texts of up to 19 digits: the same value, the same refusals, at every length and with a bad byte
// at every position.
template <class Int>
void expect_as_from_chars(const std::string& text) {
  Int expected = 7, got = 7;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, expected);
  const bool ok = ec == std::errc{} && ptr == end && !text.empty() && !(std::is_unsigned_v<Int> && text[0] == '-');
  if (!ok) expected = 7;
  EXPECT_EQ(parse_integer(text, got), ok) << text;
  EXPECT_EQ(got, expected) << text;
}

TEST(ParseInteger, SixtyFourBitDecimalsAsFromChars) {
  for (const char* text : {"0", "00", "-0", "9", "12345678", "123456789", "1762872545550296135",
                           "9223372036854775807", "9223372036854775808", "-9223372036854775808",
                           "-9223372036854775809", "9999999999999999999", "18446744073709551615",
                           "18446744073709551616", "0000000000000000000001", "12345678/", "1234567:",
                           "12345678 ", "1234567\x7f", "+1"}) {
    expect_as_from_chars<std::int64_t>(text);
    expect_as_from_chars<std::uint64_t>(text);
  }
  std::mt19937_64 rng(19);
  for (int i = 0; i < 20000; ++i) {
    std::string text = std::to_string(rng() >> (rng() % 64));
    if (i % 2 == 1) text[rng() % text.size()] = static_cast<char>(rng() % 256);  // a byte of any value
    if (i % 5 == 0) text.insert(0, "-");
    expect_as_from_chars<std::int64_t>(text);
    expect_as_from_chars<std::uint64_t>(text);
  }
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
