// The reference rig's export CSV: one timestamp per row, "Line,Seconds,Nanoseconds".
//
//   Line,Seconds,Nanoseconds
//   16,1762872545,550296135
//
// Line is the GPIO pin (or a label); Seconds and Nanoseconds are integers that together give the
// CLOCK_REALTIME time of the edge (Seconds since 1970, Nanoseconds in [0, 10^9)). The rig's
// export.sh writes a row counter in Line (0, 1, 2 ...) and the pin in the file's name
// ("<name>_measuremest_<pin>.csv"): a Line that counts the rows is read as that one pin (channel
// "gpio<pin>"; "line" when the name holds none).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

inline constexpr std::array<std::string_view, 3> kRigExportColumns{"Line", "Seconds", "Nanoseconds"};

// Imports every row as an event of ImportOptions::node, channel "gpio<Line>" for a numeric Line,
// the Line label otherwise, or ImportOptions::channel; clock realtime, edge ImportOptions::edge,
// flags imported and no-kernel-seqno. Throws core::Error(data) naming file, line and field for
// anything malformed; a file with a header and no rows gives no events.
EventImport import_rig_export_csv(std::string_view text, std::string_view name, const ImportOptions& options);

// The label every row takes when Line counts the rows: the pin of the file's name, or "line"; empty
// when Line is a pin or label of its own.
std::string rig_export_line_label(std::string_view text, std::string_view name);

// The lean import: the timestamps per Line, in order of first appearance, without events.
// `only_line` (a Line value, or empty for all) filters. Same checks and errors.
std::vector<TimestampSeries> scan_rig_export_timestamps(std::string_view text, std::string_view name,
                                                        std::string_view only_line = {});

}  // namespace m2mlat::formats
