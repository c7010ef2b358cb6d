// Numbers read from text that must be a number as a whole: a field of a file, a word of another
// program's output, a flag's value, a header. "12x", " 12", "+12", "" and values outside the type's
// range are refused (false), never cut short, wrapped or rounded to fit. Integers are parsed as
// integers (std::from_chars), never through double: a double holds an epoch timestamp in ns only to
// 256 ns. The one parser of whole-text numbers; a number inside a longer text (a prefix, a streamed
// token) is the reader's own business. Durations and seconds with units are core/time.hpp's.
#pragma once

#include <bit>
#include <charconv>
#include <concepts>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string_view>
#include <system_error>
#include <type_traits>

namespace m2mlat::core {

namespace detail {

// The value of 8 ASCII digits at p (p[0] the most significant), or false if any byte is not a digit:
// three multiplications instead of eight dependent multiply-adds and eight branches. Little-endian
// loads only (x86-64, arm64); parse_decimal19 takes the byte loop elsewhere.
inline bool eight_digits(const char* p, std::uint64_t& value) {
  std::uint64_t chunk = 0;
  std::memcpy(&chunk, p, 8);
  // Every byte 0x30-0x39: its high nibble is 3, and adding 6 to its low nibble does not carry into
  // the high one (a low nibble of at most 15 plus 6 carries at most into its own byte).
  constexpr std::uint64_t high = 0xF0F0F0F0F0F0F0F0u, threes = 0x3030303030303030u;
  if ((chunk & high) != threes || ((chunk + 0x0606060606060606u) & high) != threes) return false;
  chunk -= threes;
  chunk = (chunk * 10 + (chunk >> 8)) & 0x00FF00FF00FF00FFu;       // pairs of digits, 0-99
  chunk = (chunk * 100 + (chunk >> 16)) & 0x0000FFFF0000FFFFu;     // groups of four, 0-9999
  value = (chunk * 10000 + (chunk >> 32)) & 0xFFFFFFFFu;           // the eight, 0-99999999
  return true;
}

// Up to 19 ASCII digits (anything below 10^19 fits an uint64) as a number; false for any other byte.
// Exact: the same value std::from_chars gives.
inline bool parse_decimal19(const char* p, std::size_t n, std::uint64_t& value) {
  std::uint64_t v = 0;
  if constexpr (std::endian::native == std::endian::little) {
    for (; n >= 8; p += 8, n -= 8) {
      std::uint64_t eight = 0;
      if (!eight_digits(p, eight)) return false;
      v = v * 100'000'000u + eight;
    }
  }
  for (; n > 0; ++p, --n) {
    const auto d = static_cast<unsigned char>(*p - '0');
    if (d > 9) return false;
    v = v * 10 + d;
  }
  value = v;
  return true;
}

}  // namespace detail

// The whole text as an integer of type Int in `base` (2..36): [-]digits for a signed type, digits
// only for an unsigned one. No '+', no spaces, no "0x" prefix. `value` is unchanged on false.
template <std::integral Int>
bool parse_integer(std::string_view text, Int& value, int base = 10) {
  if (text.empty()) return false;
  if constexpr (std::is_unsigned_v<Int>)
    if (text.front() == '-') return false;
  // The fast path of 64-bit decimals (timestamps in ns: 19 digits on every line of a kernel log).
  // Longer texts (leading zeros) take std::from_chars; both give the same value and the same refusals.
  if constexpr (sizeof(Int) == 8) {
    if (base == 10) {
      const bool negative = std::is_signed_v<Int> && text.front() == '-';
      const std::string_view digits = text.substr(negative ? 1 : 0);
      if (!digits.empty() && digits.size() <= 19) {
        std::uint64_t magnitude = 0;
        if (!detail::parse_decimal19(digits.data(), digits.size(), magnitude)) return false;
        constexpr auto max = static_cast<std::uint64_t>(std::numeric_limits<Int>::max());
        if (magnitude > max + (negative ? 1u : 0u)) return false;
        // Two's complement (C++20): 0 - magnitude is the negative value, INT64_MIN included.
        value = static_cast<Int>(negative ? 0u - magnitude : magnitude);
        return true;
      }
    }
  }
  Int parsed{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, parsed, base);
  if (ec != std::errc{} || ptr != end) return false;
  value = parsed;
  return true;
}

// The whole text as a double: an optional sign ('+' or '-'), then decimal or exponent notation
// (std::from_chars, general format; "inf" and "nan" too: callers that need a finite value check
// std::isfinite). `value` is unchanged on false.
bool parse_double(std::string_view text, double& value);

}  // namespace m2mlat::core
