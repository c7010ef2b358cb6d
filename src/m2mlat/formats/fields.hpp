// Fields of delimited text: CSV splitting, exact integer fields, and the error messages that name
// the file, the line and the field ("results.csv:17: field vehicle_ns: '12x' is not an integer").
//
// Numbers are parsed whole into integers by core::parse_integer (core/number.hpp), never through
// double: a double holds an epoch timestamp in nanoseconds only to 256 ns.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/number.hpp"

namespace m2mlat::formats {

// The text without surrounding spaces and tabs.
constexpr std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

constexpr bool is_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// Splits one CSV line at its commas into `fields` (cleared first; its capacity is reused, so a
// loop over lines allocates nothing). A field may be enclosed in double quotes, inside which commas
// do not split and "" stands for one quote; the views keep their quotes (see field_text). Spaces
// around a field are trimmed. Returns false for an unterminated quote.
bool split_csv(std::string_view line, std::vector<std::string_view>& fields);

// The text of a field: its enclosing quotes removed and "" turned into ".
std::string field_text(std::string_view field);

// True if the field needs quotes in CSV output (a comma, a quote, spaces at either end, or a
// leading '#', which would read as a comment line).
bool needs_csv_quotes(std::string_view text);
// Appends the field to `out`, quoted if needed.
void append_csv_field(std::string& out, std::string_view text);

// seconds * 10^9 + nanoseconds, false on int64 overflow.
inline bool combine_seconds(std::int64_t seconds, std::int64_t nanoseconds, std::int64_t& ns) {
  std::int64_t scaled = 0;
  return !__builtin_mul_overflow(seconds, std::int64_t{1'000'000'000}, &scaled) &&
         !__builtin_add_overflow(scaled, nanoseconds, &ns);
}

// Splits nanoseconds since the epoch into whole seconds (rounded down) and nanoseconds in
// [0, 10^9), the layout of the reference rig's files (so -1 ns is -1 s + 999999999 ns).
inline void split_seconds(std::int64_t ns, std::int64_t& seconds, std::int64_t& nanoseconds) {
  seconds = ns / 1'000'000'000;
  nanoseconds = ns % 1'000'000'000;
  if (nanoseconds < 0) {
    nanoseconds += 1'000'000'000;
    seconds -= 1;
  }
}

// The offending text for a message: quoted, cut to 60 characters, control characters escaped.
std::string quote_for_message(std::string_view text);

// Throws core::Error(data): "<file>:<line>: field <field>: '<text>' <problem>".
[[noreturn]] void throw_field_error(std::string_view file, long line, std::string_view field,
                                    std::string_view text, std::string_view problem);
// Throws core::Error(data): "<file>:<line>: <what>" (line 0: "<file>: <what>").
[[noreturn]] void throw_line_error(std::string_view file, long line, const std::string& what);

// Field readers for importers: the value, or core::Error(data) naming file, line and field.
inline std::int64_t require_int64(std::string_view file, long line, std::string_view field,
                                  std::string_view text) {
  std::int64_t value = 0;
  if (!core::parse_integer(text, value)) throw_field_error(file, line, field, text, "is not an integer");
  return value;
}
inline std::uint64_t require_uint64(std::string_view file, long line, std::string_view field,
                                    std::string_view text) {
  std::uint64_t value = 0;
  if (!core::parse_integer(text, value)) throw_field_error(file, line, field, text, "is not a non-negative integer");
  return value;
}
// An integer in [0, 999999999]: the nanoseconds part of a seconds + nanoseconds pair.
inline std::int64_t require_nanoseconds(std::string_view file, long line, std::string_view field,
                                        std::string_view text) {
  const std::int64_t value = require_int64(file, line, field, text);
  if (value < 0 || value >= 1'000'000'000)
    throw_field_error(file, line, field, text, "is out of range [0, 999999999]");
  return value;
}
// Exact decimal seconds ("3942.258", up to 9 decimals) as nanoseconds.
std::int64_t require_decimal_seconds(std::string_view file, long line, std::string_view field,
                                     std::string_view text);
// Exact decimal milliseconds ("832.961", up to 6 decimals) as nanoseconds.
std::int64_t require_decimal_ms(std::string_view file, long line, std::string_view field,
                                std::string_view text);

}  // namespace m2mlat::formats
