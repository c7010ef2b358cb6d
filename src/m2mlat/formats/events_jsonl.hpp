// m2mlat's own events as JSON Lines (format m2mlat-events/2; fields in event_fields.hpp): one
// object per line, the version in its "format" member.
//
//   {"format":"m2mlat-events/2","scenario":"static_5g","session":1,"label":"run-1","node":"operator",
//    "channel":"wheel","edge":"falling","clock":"realtime","time_ns":1762872545550296135,"seqno":1041,
//    "line_seqno":17,"flag_bits":0}
//
// (one line in the file). time_ns must be a JSON integer: a float (1.762e18) would have lost the
// nanoseconds and is refused; "time_s" is accepted instead as a string of exact decimal seconds.
// scenario, session and label are null when not known (events not from a store). Version 1 lines
// ("flags", no scenario, session, label) are read too.
// Members may come in any order; edge, clock, seqno, line_seqno and flag_bits may be left out (then
// ImportOptions::edge, realtime, 0, 0, 0); unknown members are refused. A line
// {"format":"m2mlat-events/2","clock_sample":{...}} is a clock record (clock_records.hpp), not an event. Export then import gives
// back the very same events.
#pragma once

#include <ostream>
#include <span>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

// Throws core::Error(data) naming file, line and member for anything malformed.
EventImport import_events_jsonl(std::string_view text, std::string_view name, const ImportOptions& options);

// Throws core::Error(data) for an event that could not be read back (empty node, line break).
// options.clocks (clock samples and steps) are written first, one {"format":..,"clock_sample":{..}} line each.
void write_events_jsonl(std::ostream& out, std::span<const core::Event> events,
                        const EventExportOptions& options = {});

}  // namespace m2mlat::formats
