// Numbers read from text that must be a number as a whole: a field of a file, a word of another
// program's output, a flag's value, a header. "12x", " 12", "+12", "" and values outside the type's
// range are refused (false), never cut short, wrapped or rounded to fit. Integers are parsed as
// integers (std::from_chars), never through double: a double holds an epoch timestamp in ns only to
// 256 ns. The one parser of whole-text numbers; a number inside a longer text (a prefix, a streamed
// token) is the reader's own business. Durations and seconds with units are core/time.hpp's.
#pragma once

#include <charconv>
#include <concepts>
#include <string_view>
#include <system_error>
#include <type_traits>

namespace m2mlat::core {

// The whole text as an integer of type Int in `base` (2..36): [-]digits for a signed type, digits
// only for an unsigned one. No '+', no spaces, no "0x" prefix. `value` is unchanged on false.
template <std::integral Int>
bool parse_integer(std::string_view text, Int& value, int base = 10) {
  if (text.empty()) return false;
  if constexpr (std::is_unsigned_v<Int>)
    if (text.front() == '-') return false;
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
