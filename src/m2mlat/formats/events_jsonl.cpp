// Reading and writing m2mlat's own events as JSON Lines.
#include "m2mlat/formats/events_jsonl.hpp"

#include <fmt/format.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/json_fields.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

EventImport import_events_jsonl(std::string_view text, std::string_view name, const ImportOptions& options) {
  EventImport result;
  LineReader reader(text);
  std::string_view line;
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    const JsonLine json(line, name, reader.line_number());
    json.expect_format(kEventsFormat, kEventsFormatFamily, kEventsFormatV1);
    if (const auto clock = json.object().find(kClockMember); clock != json.object().end()) {
      if (json.object().size() != 2) json.fail(kClockMember, *clock, "shares its line with other members");
      if (!clock->is_object()) json.fail(kClockMember, *clock, "is not an object");
      result.clock_records.push_back(parse_clock_record(clock->dump(), name, reader.line_number()));
      continue;
    }

    core::Event event;
    event.edge = options.edge;
    core::Clock clock = core::Clock::realtime;
    std::int64_t ns = 0;
    bool has_time = false;
    for (const auto& [key, value] : json.object().items()) {
      if (key == "format") continue;
      EventField field{};
      if (!event_field_from_name(key, field)) json.unknown_member(key);
      switch (field) {
        // Where the event was recorded: checked, not kept (the import names its own session).
        case EventField::scenario:
        case EventField::label:
          if (!value.is_null() && !value.is_string()) json.fail(key, value, "is not a string");
          break;
        case EventField::session:
          if (!value.is_null()) json.int64(key, value);
          break;
        case EventField::node: event.node = json.text(key, value); break;
        case EventField::channel: event.channel = json.text(key, value); break;
        case EventField::edge:
          if (!edge_from_name(json.text(key, value), event.edge))
            json.fail(key, value, "is not rising or falling");
          break;
        case EventField::clock:
          if (!clock_from_name(json.text(key, value), clock))
            json.fail(key, value, "is not a clock (realtime, monotonic, boottime, simulated)");
          break;
        case EventField::time_ns:
          if (has_time) json.fail(key, value, "comes with time_s: give one of them");
          ns = json.int64(key, value);
          has_time = true;
          break;
        case EventField::time_s:
          if (has_time) json.fail(key, value, "comes with time_ns: give one of them");
          ns = require_decimal_seconds(name, reader.line_number(), key, json.text(key, value));
          has_time = true;
          break;
        case EventField::seqno: event.seqno = json.uint64(key, value); break;
        case EventField::line_seqno: event.line_seqno = json.uint64(key, value); break;
        case EventField::flags: {
          const std::uint64_t flags = json.uint64(key, value);
          if (flags > std::numeric_limits<std::uint32_t>::max())
            json.fail(key, value, "does not fit 32 bits");
          event.flags = static_cast<std::uint32_t>(flags);
          break;
        }
      }
    }
    if (event.node.empty()) json.missing("node");
    if (event.channel.empty()) json.missing("channel");
    if (!has_time) json.missing("time_ns");
    event.time = core::TimePoint::from_ns(clock, ns);
    result.events.push_back(std::move(event));
    ++result.records;
  }
  return result;  // no lines at all is zero events: what exporting zero events writes
}

void write_events_jsonl(std::ostream& out, std::span<const core::Event> events,
                        const EventExportOptions& options) {
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  for (const auto& record : options.clocks) {
    text.append("{\"format\":");
    append_json_string(text, kEventsFormat);
    text.append(",\"").append(kClockMember).append("\":");
    text.append(clock_record_json(record));
    text.append("}\n");
    buffer.end_record();
  }
  OriginRuns origins(options.origins, events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    const core::Event& event = events[i];
    check_exportable(event, i);
    text.append("{\"format\":");
    append_json_string(text, kEventsFormat);
    text.append(origins.json_members(i));
    text.append(",\"node\":");
    append_json_string(text, event.node);
    text.append(",\"channel\":");
    append_json_string(text, event.channel);
    text.append(",\"edge\":\"");
    text.append(core::to_string(event.edge));
    text.append("\",\"clock\":\"");
    text.append(core::to_string(event.time.clock()));
    text.append("\",\"time_ns\":");
    buffer.integer(event.time.ns());
    text.append(",\"seqno\":");
    buffer.integer(event.seqno);
    text.append(",\"line_seqno\":");
    buffer.integer(event.line_seqno);
    text.append(",\"flag_bits\":");
    buffer.integer(event.flags);
    text.append("}\n");
    buffer.end_record();
  }
  buffer.flush();
}

}  // namespace m2mlat::formats
