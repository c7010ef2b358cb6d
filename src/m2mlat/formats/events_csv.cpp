// Reading and writing m2mlat's own events CSV.
#include "m2mlat/formats/events_csv.hpp"

#include <fmt/format.h>

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);

// Which column holds each field (kAbsent if the header does not name it).
struct Layout {
  std::array<std::size_t, kEventFieldNames.size()> column{};
  std::size_t count = 0;
  std::vector<std::string> names;  // the header's columns, to notice a repeated header

  std::size_t operator[](EventField field) const { return column[static_cast<std::size_t>(field)]; }
};

std::string all_field_names() {
  std::string names;
  for (std::string_view n : kEventFieldNames) {
    if (!names.empty()) names += ", ";
    names += n;
  }
  return names;
}

// A "#" line before the header: a comment, a clock record "# clock: {...}" (added to `clocks`), or
// the format marker "# format: m2mlat-events/2" (or /1).
void check_comment(std::string_view line, std::string_view name, long line_number,
                   std::vector<ClockRecord>& clocks) {
  const std::string_view body = trim(line.substr(1));
  if (body.starts_with(kClockCommentPrefix)) {
    clocks.push_back(parse_clock_record(trim(body.substr(kClockCommentPrefix.size())), name, line_number));
    return;
  }
  if (!body.starts_with("format:")) return;
  const std::string_view marker = trim(body.substr(7));
  if (marker == kEventsFormat || marker == kEventsFormatV1) return;
  if (marker.starts_with(kEventsFormatFamily))
    throw_line_error(name, line_number,
                     fmt::format("format {} is not supported: this version of m2mlat reads {} and {}",
                                 quote_for_message(marker), kEventsFormat, kEventsFormatV1));
  throw_line_error(
      name, line_number,
      fmt::format("format {} is not an events file (expected {})", quote_for_message(marker), kEventsFormat));
}

Layout read_header(const std::vector<std::string_view>& fields, std::string_view name, long line) {
  Layout layout;
  layout.column.fill(kAbsent);
  layout.count = fields.size();
  bool any_known = false;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    EventField field{};
    if (event_field_from_name(field_text(fields[i]), field)) any_known = true;
  }
  if (!any_known)
    throw_line_error(name, line,
                     fmt::format("missing header: the first line is {}, expected a header such as "
                                 "'scenario,session,label,node,channel,edge,clock,time_ns,seqno,line_seqno,flag_bits'",
                                 quote_for_message(fields.empty() ? std::string_view{} : fields[0])));
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const std::string text = field_text(fields[i]);
    EventField field{};
    if (!event_field_from_name(text, field))
      throw_line_error(name, line,
                       fmt::format("header column {} {} is not a field of {} ({})", i + 1,
                                   quote_for_message(text), kEventsFormat, all_field_names()));
    auto& slot = layout.column[static_cast<std::size_t>(field)];
    if (slot != kAbsent)
      throw_line_error(
          name, line,
          fmt::format("header column '{}' appears twice (columns {} and {})", text, slot + 1, i + 1));
    slot = i;
  }
  for (std::string_view field : fields) layout.names.push_back(field_text(field));
  if (layout[EventField::node] == kAbsent || layout[EventField::channel] == kAbsent)
    throw_line_error(name, line, "the header needs the columns node and channel");
  const bool has_ns = layout[EventField::time_ns] != kAbsent;
  const bool has_s = layout[EventField::time_s] != kAbsent;
  if (has_ns == has_s)
    throw_line_error(name, line,
                     has_ns ? "the header has both time_ns and time_s: give one of them"
                            : "the header needs a time column: time_ns (or time_s)");
  return layout;
}

// A non-text field without its quotes, if it was quoted as a whole.
std::string_view bare(std::string_view field) {
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
    return field.substr(1, field.size() - 2);
  return field;
}

// True if the row repeats the header (two files joined with cat); cheap unless the first field matches.
bool is_header_again(const std::vector<std::string_view>& fields, const Layout& layout) {
  if (fields.size() != layout.names.size() || field_text(fields[0]) != layout.names[0]) return false;
  for (std::size_t i = 1; i < fields.size(); ++i)
    if (field_text(fields[i]) != layout.names[i]) return false;
  return true;
}

// Reads the rows, reusing node and channel strings while they stay the same.
class RowReader {
 public:
  RowReader(const Layout& layout, std::string_view name, const ImportOptions& options)
      : layout_(layout), name_(name) {
    event_.edge = options.edge;
  }

  const core::Event& read(const std::vector<std::string_view>& fields, long line) {
    line_ = line;
    text(fields[layout_[EventField::node]], EventField::node, last_node_, event_.node);
    text(fields[layout_[EventField::channel]], EventField::channel, last_channel_, event_.channel);
    // Where the event was recorded: checked, not kept (the import names its own session).
    if (const std::size_t c = layout_[EventField::session]; c != kAbsent)
      if (const std::string_view raw = bare(fields[c]); !raw.empty())
        require_int64(name_, line, "session", raw);
    if (const std::size_t c = layout_[EventField::edge]; c != kAbsent) {
      const std::string_view raw = bare(fields[c]);
      if (!edge_from_name(raw, event_.edge)) fail(EventField::edge, raw, "is not rising or falling");
    }
    if (const std::size_t c = layout_[EventField::clock]; c != kAbsent) {
      const std::string_view raw = bare(fields[c]);
      if (!clock_from_name(raw, clock_))
        fail(EventField::clock, raw, "is not a clock (realtime, monotonic, boottime, simulated)");
    }
    std::int64_t ns = 0;
    if (const std::size_t c = layout_[EventField::time_ns]; c != kAbsent)
      ns = require_int64(name_, line, "time_ns", bare(fields[c]));
    else
      ns = require_decimal_seconds(name_, line, "time_s", bare(fields[layout_[EventField::time_s]]));
    event_.time = core::TimePoint::from_ns(clock_, ns);
    if (const std::size_t c = layout_[EventField::seqno]; c != kAbsent)
      event_.seqno = require_uint64(name_, line, "seqno", bare(fields[c]));
    if (const std::size_t c = layout_[EventField::line_seqno]; c != kAbsent)
      event_.line_seqno = require_uint64(name_, line, "line_seqno", bare(fields[c]));
    if (const std::size_t c = layout_[EventField::flags]; c != kAbsent) {
      const std::string_view raw = bare(fields[c]);
      const std::uint64_t flags = require_uint64(name_, line, name_of(EventField::flags), raw);
      if (flags > std::numeric_limits<std::uint32_t>::max())
        fail(EventField::flags, raw, "does not fit 32 bits");
      event_.flags = static_cast<std::uint32_t>(flags);
    }
    return event_;
  }

 private:
  void text(std::string_view raw, EventField field, std::string_view& last, std::string& out) {
    if (raw == last && !out.empty()) return;
    out = field_text(raw);
    if (out.empty()) fail(field, raw, "is empty");
    last = raw;
  }
  [[noreturn]] void fail(EventField field, std::string_view text, std::string_view problem) const {
    throw_field_error(name_, line_, name_of(field), text, problem);
  }

  const Layout& layout_;
  std::string_view name_;
  long line_ = 0;
  core::Event event_;
  core::Clock clock_ = core::Clock::realtime;
  std::string_view last_node_;
  std::string_view last_channel_;
};

}  // namespace

EventImport import_events_csv(std::string_view text, std::string_view name, const ImportOptions& options) {
  LineReader reader(text);
  std::vector<std::string_view> fields;
  std::string_view line;
  bool found = false;
  std::vector<ClockRecord> clocks;
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    if (trim(line).front() == '#') {
      check_comment(trim(line), name, reader.line_number(), clocks);
      continue;
    }
    found = true;
    break;
  }
  if (!found) throw_line_error(name, 0, "is empty (expected a header such as 'node,channel,time_ns')");
  if (!split_csv(line, fields)) throw_line_error(name, reader.line_number(), "unterminated quote");
  const Layout layout = read_header(fields, name, reader.line_number());

  EventImport result;
  result.clock_records = std::move(clocks);
  result.events.reserve(count_lines(text));
  RowReader rows(layout, name, options);
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    const long number = reader.line_number();
    if (trim(line).front() == '#')
      throw_line_error(name, number, "a '#' line after the header (were two files joined?)");
    if (!split_csv(line, fields)) throw_line_error(name, number, "unterminated quote");
    if (bare(fields[0]) == layout.names[0] && is_header_again(fields, layout))
      throw_line_error(name, number, "the header appears again (were two files joined?)");
    if (fields.size() != layout.count)
      throw_line_error(name, number,
                       fmt::format("expected {} fields, found {}", layout.count, fields.size()));
    result.events.push_back(rows.read(fields, number));
    ++result.records;
  }
  return result;
}

void write_events_csv(std::ostream& out, std::span<const core::Event> events,
                      const EventExportOptions& options) {
  OutputBuffer buffer(out);
  if (options.with_meta) {
    buffer << "# format: " << kEventsFormat << '\n';
    for (const auto& record : options.clocks) {
      if (record.node.find_first_of("\r\n") != std::string::npos)
        throw core::Error(core::ErrorKind::data, "a clock record's node holds a line break");
      buffer << "# " << kClockCommentPrefix << ' ' << clock_record_json(record) << '\n';
      buffer.end_record();
    }
  }
  for (std::size_t i = 0; i < kExportedEventFields.size(); ++i) {
    if (i > 0) buffer << ',';
    buffer << name_of(kExportedEventFields[i]);
  }
  buffer << '\n';
  OriginRuns origins(options.origins, events.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    const core::Event& event = events[i];
    check_exportable(event, i);
    buffer.text().append(origins.csv_fields(i));
    append_csv_field(buffer.text(), event.node);
    buffer << ',';
    append_csv_field(buffer.text(), event.channel);
    buffer << ',' << core::to_string(event.edge) << ',' << core::to_string(event.time.clock()) << ',';
    buffer.integer(event.time.ns()) << ',';
    buffer.integer(event.seqno) << ',';
    buffer.integer(event.line_seqno) << ',';
    buffer.integer(event.flags) << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

}  // namespace m2mlat::formats
