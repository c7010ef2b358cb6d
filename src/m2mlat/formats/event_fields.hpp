// The fields of m2mlat's own events format, version 2, shared by its CSV and JSON Lines forms.
//
// One event per record: scenario, session (the store's session id, empty/0 = not from a store) and
// label (the session's label) say where it was recorded; node, channel, edge ("rising" | "falling"),
// clock ("realtime", "monotonic", "boottime", "simulated"), time_ns (integer ns since the clock's
// epoch; or time_s, exact decimal seconds, on import), seqno and line_seqno (the kernel's event
// numbers, 0 = none) and flag_bits (core::EventFlag bits, decimal; named so because pandas'
// DataFrame has its own `flags`). The version marker "m2mlat-events/2" is the "format" member of every
// JSON Lines object, and in a CSV the line "# format: m2mlat-events/2" before the header, written only
// on request (--with-meta): a plain CSV starts with its header, as pandas, R and DuckDB expect.
// Version 1 (no scenario, session, label; "flags") is still read; the reader refuses markers it does
// not know. On import, scenario, session and label are read and checked but not used: the import's
// own --scenario and --label name the session the events go to.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

inline constexpr std::string_view kEventsFormat = "m2mlat-events/2";
inline constexpr std::string_view kEventsFormatV1 = "m2mlat-events/1";  // read, no longer written
inline constexpr std::string_view kEventsFormatFamily = "m2mlat-events/";

enum class EventField : std::uint8_t {
  scenario,
  session,
  label,
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
inline constexpr std::array<std::string_view, 12> kEventFieldNames{
    "scenario", "session", "label", "node", "channel", "edge", "clock", "time_ns", "time_s", "seqno",
    "line_seqno", "flag_bits"};
// The name version 1 gave flag_bits, still read.
inline constexpr std::string_view kEventFlagsV1Name = "flags";
// The columns the exporter writes, in this order (time_s is accepted on import only).
inline constexpr std::array<EventField, 11> kExportedEventFields{
    EventField::scenario, EventField::session, EventField::label,      EventField::node,
    EventField::channel,  EventField::edge,    EventField::clock,      EventField::time_ns,
    EventField::seqno,    EventField::line_seqno, EventField::flags};

// Where a run of consecutive exported events was recorded: one run per stored session (`count`
// events), so that every row names its scenario, session and label without a copy per event.
struct EventOrigin {
  std::string scenario;
  std::int64_t session = 0;  // the store's session id
  std::string label;
  std::size_t count = 0;
};

struct EventExportOptions {
  std::span<const ClockRecord> clocks;   // the nodes' clock samples and steps (clock_records.hpp)
  std::span<const EventOrigin> origins;  // empty: scenario, session and label are left empty
  // CSV only: the "# format:" line and the clock records as "# clock: {...}" lines before the header
  // (the form m2mlat-events/1 always had). Without it, a CSV is its header and rows only, and the
  // clock records are not written (the caller says so). JSON Lines always carries both.
  bool with_meta = false;
};
inline constexpr std::string_view name_of(EventField field) {
  return kEventFieldNames[static_cast<std::size_t>(field)];
}
// The scenario, session and label text of each exported event, walking the origins' runs in order:
// csv_fields(i) is "scenario,session,label," (quoted as needed) and json_members(i)
// ',"scenario":..,"session":..,"label":..' for event i, i increasing. Throws core::Error(internal) if
// non-empty origins do not count `events` events, core::Error(data) for a name with a line break.
class OriginRuns {
 public:
  OriginRuns(std::span<const EventOrigin> origins, std::size_t events);
  const std::string& csv_fields(std::size_t index) { return advance(index).csv; }
  const std::string& json_members(std::size_t index) { return advance(index).json; }

 private:
  struct Text {
    std::string csv, json;
  };
  const Text& advance(std::size_t index);
  std::span<const EventOrigin> origins_;
  std::size_t run_ = 0;
  std::size_t run_end_ = 0;  // one past the last event of run_
  Text text_;
};

// False if `name` is not a field of the format (version 1's "flags" is flag_bits).
bool event_field_from_name(std::string_view name, EventField& field);

// Edge and clock names as written in the files; false for an unknown name (the importers turn
// that into an error naming file, line and field).
bool edge_from_name(std::string_view name, core::Edge& edge);
bool clock_from_name(std::string_view name, core::Clock& clock);

// Throws core::Error(data) if the event cannot be written so that it reads back the same: an empty
// node or channel, or one with a line break. `index` is its position, for the message.
void check_exportable(const core::Event& event, std::size_t index);

}  // namespace m2mlat::formats
