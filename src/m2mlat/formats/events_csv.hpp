// m2mlat's own events CSV (format m2mlat-events/2; the fields are described in event_fields.hpp).
//
//   scenario,session,label,node,channel,edge,clock,time_ns,seqno,line_seqno,flag_bits
//   static_5g,1,run-1,operator,wheel,falling,realtime,1762872545550296135,1041,17,0
//
// Export writes exactly this; with EventExportOptions::with_meta, the lines "# format:
// m2mlat-events/2" and "# clock: {...}" come before the header. Import also accepts: version 1 files
// (no scenario, session, label; "flags" for flag_bits), other "#" comment lines
// before the header, the columns in any order, time_s (exact decimal seconds) instead of time_ns,
// and any of edge, clock, seqno, line_seqno, flags left out (then ImportOptions::edge, realtime, 0,
// 0, 0), and "# clock: {...}" lines (clock_records.hpp: the clock samples and steps of the
// nodes) among the comments before the header. Fields with a comma or quote are double-quoted, a quote doubled. Export then import gives
// back the very same events.
#pragma once

#include <ostream>
#include <span>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

// Throws core::Error(data) naming file, line and field for anything malformed, an unknown or
// repeated column, or a format marker other than m2mlat-events/1. Events are returned as written:
// flags are not changed.
EventImport import_events_csv(std::string_view text, std::string_view name, const ImportOptions& options);

// Throws core::Error(data) for an event that could not be read back (empty node, line break), and
// core::Error(internal) if options.origins do not count the events.
// `options.clocks` (clock samples and steps) go before the header as "# clock: {...}" lines when
// options.with_meta; they are not written otherwise.
void write_events_csv(std::ostream& out, std::span<const core::Event> events,
                      const EventExportOptions& options = {});

}  // namespace m2mlat::formats
