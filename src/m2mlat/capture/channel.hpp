// A channel's configuration: which line of which chip, and how the kernel should watch it. Shared
// by the TOML configuration, the command-line flags and the sources.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

enum class Edges : std::uint8_t { falling, rising, both };
enum class Bias : std::uint8_t { as_is, pull_up, pull_down, disabled };
// The clock the kernel stamps events with. hte: a hardware timestamp engine, where the SoC has one.
enum class EventClock : std::uint8_t { realtime, monotonic, hte };

std::string_view to_string(Edges edges);
std::string_view to_string(Bias bias);
std::string_view to_string(EventClock clock);
// Parse the words of the command line and the TOML file; throw core::Error(usage) listing the choices.
Edges parse_edges(std::string_view text);             // falling | rising | both
Bias parse_bias(std::string_view text);               // as-is | pull-up | pull-down | disabled
EventClock parse_event_clock(std::string_view text);  // realtime | monotonic | hte
// The core::Clock an event clock's timestamps are on. HTE providers (Tegra's GTE) count the
// system counter, the base of CLOCK_MONOTONIC, so hte stamps are stored as monotonic.
core::Clock stored_clock(EventClock clock);

struct ChannelSpec {
  std::string name;              // the channel's name in the store, e.g. "wheel"
  std::string chip;              // path (/dev/gpiochip4), name (gpiochip4) or label (pinctrl-rp1)
  std::string line;              // offset ("16") or line name ("GPIO16")
  Edges edges = Edges::falling;  // the reference rig's A3144 pulls the line low when a magnet passes
  Bias bias = Bias::as_is;
  bool active_low = false;
  EventClock clock = EventClock::realtime;
  // Kernel debounce. 0 = none (the default): with debounce the kernel stamps the edge in a work item
  // after the period, not in the hard IRQ, so every timestamp is late. Use `refractory` instead.
  core::Duration debounce{0};
  // User-space refractory period: edges closer than this after a kept edge are counted, not stored.
  core::Duration refractory{0};
};

// "wheel=pinctrl-rp1:GPIO16" -> name, chip, line (the rest left at defaults). The line is after the
// last ':'; the chip may be empty ("wheel=:16") for the kmsg source, which has no chips. Throws
// core::Error(usage).
ChannelSpec parse_channel_flag(std::string_view text);

}  // namespace m2mlat::capture
