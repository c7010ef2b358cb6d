// Exact integer parsing and formatting of nanosecond times: no step goes through double.
#include "m2mlat/core/time.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdlib>
#include <limits>

#include "m2mlat/core/error.hpp"

namespace m2mlat::core {

namespace {
constexpr std::array<std::string_view, 4> kClockNames{"realtime", "monotonic", "boottime", "simulated"};

// Parses [-]digits[.digits] into an integer scaled by 10^decimals. False on bad text or overflow.
bool parse_fixed(std::string_view text, int decimals, std::int64_t& out) {
  if (text.empty()) return false;
  bool negative = false;
  if (text.front() == '-' || text.front() == '+') {
    negative = text.front() == '-';
    text.remove_prefix(1);
  }
  const auto dot = text.find('.');
  std::string_view whole = text.substr(0, dot);
  std::string_view frac = dot == std::string_view::npos ? std::string_view{} : text.substr(dot + 1);
  if (whole.empty() && frac.empty()) return false;
  if (dot != std::string_view::npos && frac.empty() && whole.empty()) return false;
  if (static_cast<int>(frac.size()) > decimals) return false;
  constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
  std::int64_t value = 0;
  auto push = [&](char c) {
    if (c < '0' || c > '9') return false;
    const int digit = c - '0';
    if (value > (kMax - digit) / 10) return false;
    value = value * 10 + digit;
    return true;
  };
  for (char c : whole)
    if (!push(c)) return false;
  for (char c : frac)
    if (!push(c)) return false;
  for (int i = static_cast<int>(frac.size()); i < decimals; ++i)
    if (!push('0')) return false;
  out = negative ? -value : value;
  return true;
}

std::string format_fixed(std::int64_t value, std::int64_t scale, int decimals) {
  // Work in unsigned magnitude so INT64_MIN does not overflow.
  const bool negative = value < 0;
  const std::uint64_t mag =
      negative ? std::uint64_t{0} - static_cast<std::uint64_t>(value) : static_cast<std::uint64_t>(value);
  const auto uscale = static_cast<std::uint64_t>(scale);
  return fmt::format("{}{}.{:0{}}", negative ? "-" : "", mag / uscale, mag % uscale, decimals);
}
}  // namespace

std::string_view to_string(Clock clock) { return kClockNames.at(static_cast<std::size_t>(clock)); }

Clock parse_clock(std::string_view text) {
  for (std::size_t i = 0; i < kClockNames.size(); ++i)
    if (kClockNames[i] == text) return static_cast<Clock>(i);
  throw Error(ErrorKind::usage,
              fmt::format("unknown clock '{}' (expected realtime, monotonic, boottime or simulated)", text));
}

Duration TimePoint::operator-(const TimePoint& other) const {
  if (clock_ != other.clock_)
    throw Error(ErrorKind::internal, fmt::format("subtracting a {} timestamp from a {} timestamp",
                                                 to_string(other.clock_), to_string(clock_)));
  return since_epoch_ - other.since_epoch_;
}

std::string format_seconds(std::int64_t ns) { return format_fixed(ns, 1'000'000'000, 9); }

std::string format_ms(Duration d) { return format_fixed(d.count(), 1'000'000, 6); }

bool parse_seconds(std::string_view text, std::int64_t& ns) { return parse_fixed(text, 9, ns); }

bool parse_ms(std::string_view text, std::int64_t& ns) { return parse_fixed(text, 6, ns); }

Duration parse_duration(std::string_view text, std::int64_t default_unit_ns) {
  struct Unit {
    std::string_view suffix;
    std::int64_t ns;
    int decimals;  // digits after the point that still give whole nanoseconds
  };
  // Longest suffixes first so "ms" is not read as "s".
  static constexpr std::array<Unit, 7> kUnits{{{"min", 60'000'000'000, 9},
                                               {"ns", 1, 0},
                                               {"us", 1'000, 3},
                                               {"µs", 1'000, 3},
                                               {"ms", 1'000'000, 6},
                                               {"h", 3'600'000'000'000, 9},
                                               {"s", 1'000'000'000, 9}}};
  const std::string shown(text);
  for (const auto& unit : kUnits) {
    if (text.size() > unit.suffix.size() && text.ends_with(unit.suffix)) {
      std::int64_t scaled = 0;  // value * 10^decimals
      if (!parse_fixed(text.substr(0, text.size() - unit.suffix.size()), unit.decimals, scaled)) break;
      std::int64_t pow10 = 1;
      for (int i = 0; i < unit.decimals; ++i) pow10 *= 10;
      return Duration{scaled * (unit.ns / pow10)};  // every unit is a whole multiple of 10^-decimals
    }
  }
  if (default_unit_ns > 0) {
    std::int64_t scaled = 0;
    if (parse_fixed(text, 0, scaled)) return Duration{scaled * default_unit_ns};
  }
  throw Error(ErrorKind::usage,
              fmt::format("'{}' is not a duration (examples: 800ms, 3s, 250us, 10ns)", shown));
}

std::string format_duration(Duration d) {
  const std::int64_t ns = d.count();
  const std::int64_t mag = ns < 0 ? -ns : ns;
  if (mag >= 1'000'000'000) return format_fixed(ns / 1'000'000, 1'000, 3) + " s";
  if (mag >= 1'000'000) return format_fixed(ns / 1'000, 1'000, 3) + " ms";
  if (mag >= 1'000) return format_fixed(ns, 1'000, 3) + " us";
  return fmt::format("{} ns", ns);
}

}  // namespace m2mlat::core
