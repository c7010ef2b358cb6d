// Time as the kernel gives it: int64 nanoseconds, tagged with the clock it was read from.
//
// A double holds a nanosecond epoch timestamp only to 256 ns, so no timestamp or duration in
// m2mlat is ever a double; floating point appears only in statistics, after two integer
// timestamps of the same clock have been subtracted.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace m2mlat::core {

// Durations: signed 64-bit nanoseconds (std::chrono::nanoseconds is int64 on every target).
using Duration = std::chrono::nanoseconds;
static_assert(sizeof(Duration::rep) == 8, "Duration must be int64 nanoseconds");

// The clock a timestamp was read from. Values are stored in files and databases: never renumber.
enum class Clock : std::uint8_t {
  realtime = 0,   // CLOCK_REALTIME: UTC since 1970, disciplined by chrony/PTP; comparable across boards
  monotonic = 1,  // CLOCK_MONOTONIC: since boot, slewed but never stepped; comparable on one board only
  boottime = 2,   // CLOCK_BOOTTIME: monotonic including suspend
  simulated = 3,  // the simulator's own ground-truth time base
};

std::string_view to_string(Clock clock);
// Parses "realtime", "monotonic", "boottime", "simulated"; throws core::Error(kind=usage) otherwise.
Clock parse_clock(std::string_view text);

// A point in time on a named clock. Subtracting two time points of different clocks is a
// programming error and throws: the difference would have no meaning.
class TimePoint {
 public:
  constexpr TimePoint() = default;
  constexpr TimePoint(Clock clock, Duration since_epoch) : clock_(clock), since_epoch_(since_epoch) {}
  static constexpr TimePoint from_ns(Clock clock, std::int64_t ns) { return {clock, Duration{ns}}; }

  constexpr Clock clock() const { return clock_; }
  constexpr Duration since_epoch() const { return since_epoch_; }
  constexpr std::int64_t ns() const { return since_epoch_.count(); }

  constexpr TimePoint operator+(Duration d) const { return {clock_, since_epoch_ + d}; }
  constexpr TimePoint operator-(Duration d) const { return {clock_, since_epoch_ - d}; }
  Duration operator-(const TimePoint& other) const;

  friend constexpr bool operator==(const TimePoint&, const TimePoint&) = default;
  // Ordering is by clock first, then time: only meaningful within one clock.
  friend constexpr auto operator<=>(const TimePoint&, const TimePoint&) = default;

 private:
  Clock clock_ = Clock::realtime;
  Duration since_epoch_{0};
};

// Exact decimal text for seconds.nanoseconds, e.g. 1762872545.550296135 (always 9 decimals).
std::string format_seconds(std::int64_t ns);
// Milliseconds with 6 decimals, exact: 867289327 ns -> "867.289327".
std::string format_ms(Duration d);
// Parses a decimal seconds value without going through double: "1762872545.550296135",
// "-0.5", "12" -> ns. Up to 9 decimals; more digits is an error (no silent rounding).
// Returns false on malformed text or overflow.
bool parse_seconds(std::string_view text, std::int64_t& ns);
// Parses a decimal milliseconds value ("867.289327", up to 6 decimals) exactly into ns.
bool parse_ms(std::string_view text, std::int64_t& ns);
// Parses a duration with unit: "800ms", "3s", "1.5s", "250us", "10ns", "2min"; a bare number
// needs `default_unit_ns` (e.g. 1'000'000 for ms). Throws core::Error(kind=usage) with the text.
Duration parse_duration(std::string_view text, std::int64_t default_unit_ns = 0);
// Human-readable duration with a fitting unit: "812.345 ms", "3.000 s", "250 ns".
std::string format_duration(Duration d);

}  // namespace m2mlat::core
