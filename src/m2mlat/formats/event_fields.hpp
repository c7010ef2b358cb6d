// The fields of m2mlat's own events format, version 1, shared by its CSV and JSON Lines forms.
//
// One event per record: node, channel, edge ("rising" | "falling"), clock ("realtime", "monotonic",
// "boottime", "simulated"), time_ns (integer ns since the clock's epoch; or time_s, exact decimal
// seconds, on import), seqno and line_seqno (the kernel's event numbers, 0 = none) and flags
// (core::EventFlag bits, decimal). The version marker "m2mlat-events/1" is the first line of a CSV
// ("# format: m2mlat-events/1") and the "format" member of every JSON Lines object. A later version
// gets a new marker; this reader refuses markers it does not know.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

#include "m2mlat/core/event.hpp"

namespace m2mlat::formats {

inline constexpr std::string_view kEventsFormat = "m2mlat-events/1";
inline constexpr std::string_view kEventsFormatFamily = "m2mlat-events/";

enum class EventField : std::uint8_t {
  node,
  channel,
  edge,
  clock,
  time_ns,
  time_s,
  seqno,
  line_seqno,
  flags
};
inline constexpr std::array<std::string_view, 9> kEventFieldNames{
    "node", "channel", "edge", "clock", "time_ns", "time_s", "seqno", "line_seqno", "flags"};
// The columns the exporter writes, in this order (time_s is accepted on import only).
inline constexpr std::array<EventField, 8> kExportedEventFields{
    EventField::node,    EventField::channel, EventField::edge,       EventField::clock,
    EventField::time_ns, EventField::seqno,   EventField::line_seqno, EventField::flags};

inline constexpr std::string_view name_of(EventField field) {
  return kEventFieldNames[static_cast<std::size_t>(field)];
}
// False if `name` is not a field of the format.
bool event_field_from_name(std::string_view name, EventField& field);

// Edge and clock names as written in the files; false for an unknown name (the importers turn
// that into an error naming file, line and field).
bool edge_from_name(std::string_view name, core::Edge& edge);
bool clock_from_name(std::string_view name, core::Clock& clock);

// Throws core::Error(data) if the event cannot be written so that it reads back the same: an empty
// node or channel, or one with a line break. `index` is its position, for the message.
void check_exportable(const core::Event& event, std::size_t index);

}  // namespace m2mlat::formats
