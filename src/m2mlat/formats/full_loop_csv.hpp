// The other full-loop rig's result CSV: one teleoperation event per row, six CLOCK_REALTIME
// timestamps in int64 nanoseconds since the Unix epoch.
//
//   VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR
//   1762872546417585462,1762872546917585462,1762872546417601000,1762872545550296135,...
//
// The *_GY_ON/OFF columns are the motion onset and end each side's gyroscope detected, LED_ON the
// time the vehicle switched the LED in its camera's view, PHOTOTRANSISTOR the time the operator's
// screen showed it. What is tolerated (docs/formats.md): the columns in any order, found by name
// (each of the six exactly once, no other); spaces around a field; a BOM, CRLF line ends and blank
// lines. An empty field is that event's value missing (the analysis counts it, it is never a zero).
// Anything else (a non-number, a value outside int64, a wrong field count, a quoted field, the
// header again, a last line cut mid-write) is refused naming file, line and column.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace m2mlat::formats {

// The columns in the rig's own order; FullLoopRow::ns is indexed by this order whatever the file's.
inline constexpr std::array<std::string_view, 6> kFullLoopColumns{
    "VEHICLE_GY_ON", "VEHICLE_GY_OFF", "LED_ON", "STATION_GY_ON", "STATION_GY_OFF", "PHOTOTRANSISTOR"};

enum FullLoopColumn : std::size_t {
  kVehicleGyOn = 0,
  kVehicleGyOff = 1,
  kLedOn = 2,
  kStationGyOn = 3,
  kStationGyOff = 4,
  kPhototransistor = 5
};

struct FullLoopRow {
  long line = 0;  // the row's line in the file (1-based, blank lines counted)
  // CLOCK_REALTIME ns since 1970 by FullLoopColumn; nullopt where the field was empty.
  std::array<std::optional<std::int64_t>, kFullLoopColumns.size()> ns{};
  friend bool operator==(const FullLoopRow&, const FullLoopRow&) = default;
};

struct FullLoopImport {
  std::vector<FullLoopRow> rows;  // in file order
};

// True if a header's fields name at least three of the six columns: detection takes such a file
// for this format, so that a header with a column misspelt gets this reader's precise message.
bool looks_like_full_loop_header(std::span<const std::string_view> fields);

// Throws core::Error(data) naming file, line and field for anything malformed (see above).
FullLoopImport import_full_loop_csv(std::string_view text, std::string_view name);

}  // namespace m2mlat::formats
