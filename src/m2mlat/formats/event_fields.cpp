// Field names, edge and clock names, and export checks of the m2mlat-events format.
#include "m2mlat/formats/event_fields.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

bool event_field_from_name(std::string_view name, EventField& field) {
  for (std::size_t i = 0; i < kEventFieldNames.size(); ++i) {
    if (kEventFieldNames[i] == name) {
      field = static_cast<EventField>(i);
      return true;
    }
  }
  if (name == kEventFlagsV1Name) {
    field = EventField::flags;
    return true;
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

OriginRuns::OriginRuns(std::span<const EventOrigin> origins, std::size_t events) : origins_(origins) {
  std::size_t total = 0;
  for (const auto& origin : origins) {
    total += origin.count;
    for (const std::string* text : {&origin.scenario, &origin.label})
      if (text->find_first_of("\r\n") != std::string::npos)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("session {}: a scenario or label with a line break", origin.session));
  }
  if (!origins.empty() && total != events)
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("event export: the origins count {} events, not {}", total, events));
  text_.csv = ",,,";
  text_.json = R"(,"scenario":null,"session":null,"label":null)";
  run_ = static_cast<std::size_t>(-1);
}

const OriginRuns::Text& OriginRuns::advance(std::size_t index) {
  if (origins_.empty()) return text_;
  while (run_ == static_cast<std::size_t>(-1) || index >= run_end_) {
    run_ = run_ == static_cast<std::size_t>(-1) ? 0 : run_ + 1;
    const EventOrigin& origin = origins_[run_];
    run_end_ = (run_ == 0 ? 0 : run_end_) + origin.count;
    if (origin.count == 0) continue;
    text_.csv.clear();
    append_csv_field(text_.csv, origin.scenario);
    text_.csv += fmt::format(",{},", origin.session);
    append_csv_field(text_.csv, origin.label);
    text_.csv += ',';
    text_.json = R"(,"scenario":)";
    append_json_string(text_.json, origin.scenario);
    text_.json += fmt::format(R"(,"session":{},"label":)", origin.session);
    append_json_string(text_.json, origin.label);
  }
  return text_;
}

}  // namespace m2mlat::formats
