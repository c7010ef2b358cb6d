// Words of the channel settings and the --channel flag.
#include "m2mlat/capture/channel.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

std::string_view to_string(Edges edges) {
  switch (edges) {
    case Edges::falling: return "falling";
    case Edges::rising: return "rising";
    case Edges::both: return "both";
  }
  return "?";
}

std::string_view to_string(Bias bias) {
  switch (bias) {
    case Bias::as_is: return "as-is";
    case Bias::pull_up: return "pull-up";
    case Bias::pull_down: return "pull-down";
    case Bias::disabled: return "disabled";
  }
  return "?";
}

std::string_view to_string(EventClock clock) {
  switch (clock) {
    case EventClock::realtime: return "realtime";
    case EventClock::monotonic: return "monotonic";
    case EventClock::hte: return "hte";
  }
  return "?";
}

Edges parse_edges(std::string_view text) {
  if (text == "falling") return Edges::falling;
  if (text == "rising") return Edges::rising;
  if (text == "both") return Edges::both;
  throw core::Error(core::ErrorKind::usage, fmt::format("edges '{}': use falling, rising or both", text));
}

Bias parse_bias(std::string_view text) {
  if (text == "as-is") return Bias::as_is;
  if (text == "pull-up") return Bias::pull_up;
  if (text == "pull-down") return Bias::pull_down;
  if (text == "disabled") return Bias::disabled;
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("bias '{}': use as-is, pull-up, pull-down or disabled", text));
}

EventClock parse_event_clock(std::string_view text) {
  if (text == "realtime") return EventClock::realtime;
  if (text == "monotonic") return EventClock::monotonic;
  if (text == "hte") return EventClock::hte;
  throw core::Error(core::ErrorKind::usage, fmt::format("clock '{}': use realtime, monotonic or hte", text));
}

core::Clock stored_clock(EventClock clock) {
  return clock == EventClock::realtime ? core::Clock::realtime : core::Clock::monotonic;
}

ChannelSpec parse_channel_flag(std::string_view text) {
  const auto eq = text.find('=');
  const auto colon = text.rfind(':');
  if (eq == std::string_view::npos || eq == 0 || colon == std::string_view::npos || colon < eq + 1 ||
      colon + 1 == text.size())
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("--channel '{}': expected NAME=CHIP:LINE, e.g. wheel=pinctrl-rp1:GPIO16", text));
  ChannelSpec spec;
  spec.name = std::string(text.substr(0, eq));
  spec.chip = std::string(text.substr(eq + 1, colon - eq - 1));
  spec.line = std::string(text.substr(colon + 1));
  return spec;
}

}  // namespace m2mlat::capture
