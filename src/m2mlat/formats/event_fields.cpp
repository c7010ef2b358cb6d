// Field names, edge and clock names, and export checks of the m2mlat-events format.
#include "m2mlat/formats/event_fields.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats {

bool event_field_from_name(std::string_view name, EventField& field) {
  for (std::size_t i = 0; i < kEventFieldNames.size(); ++i) {
    if (kEventFieldNames[i] == name) {
      field = static_cast<EventField>(i);
      return true;
    }
  }
  return false;
}

bool edge_from_name(std::string_view name, core::Edge& edge) {
  if (name == "falling") {
    edge = core::Edge::falling;
    return true;
  }
  if (name == "rising") {
    edge = core::Edge::rising;
    return true;
  }
  return false;
}

bool clock_from_name(std::string_view name, core::Clock& clock) {
  for (const core::Clock candidate :
       {core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime, core::Clock::simulated}) {
    if (core::to_string(candidate) == name) {
      clock = candidate;
      return true;
    }
  }
  return false;
}

void check_exportable(const core::Event& event, std::size_t index) {
  auto check = [&](std::string_view what, const std::string& text) {
    if (text.empty())
      throw core::Error(core::ErrorKind::data, fmt::format("event {}: the {} name is empty", index, what));
    if (text.find_first_of("\r\n") != std::string::npos)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("event {}: the {} name contains a line break", index, what));
  };
  check("node", event.node);
  check("channel", event.channel);
}

}  // namespace m2mlat::formats
