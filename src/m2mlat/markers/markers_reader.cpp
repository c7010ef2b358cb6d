#include "m2mlat/markers/markers_reader.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/markers/markers_file.hpp"

namespace m2mlat::markers {

namespace {

constexpr std::string_view kMarkersHeader =
    "node,name,clock,time_ns,source,key,sender_ns,sender_to_capture_ns,origin";

StampSource read_stamp_source(std::string_view file, long line, std::string_view text) {
  if (const auto source = parse_stamp_source(text)) return *source;
  formats::throw_field_error(file, line, "source", text,
                             "is not adapter, host, file, kernel, receiver, bag_log or bag_header");
}

}  // namespace

std::vector<Marker> parse_markers_csv(std::string_view text, std::string_view name) {
  formats::check_input(text, name);
  formats::LineReader reader(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  std::vector<Marker> out;
  bool header_seen = false;
  while (reader.next(line)) {
    const long n = reader.line_number();
    const auto content = formats::trim(line);
    if (content.empty()) continue;
    if (content.front() == '#') {
      if (content.starts_with("# format:")) {
        const auto f = formats::trim(content.substr(9));
        if (f != kMarkersFormat)
          formats::throw_line_error(name, n, fmt::format("format {}, expected {}", formats::quote_for_message(f),
                                                         kMarkersFormat));
      }
      continue;
    }
    if (!header_seen) {
      // The header identifies the file; older files have a "# format:" line before it (checked above).
      if (content != kMarkersHeader)
        formats::throw_line_error(name, n, fmt::format("header {}, expected {}", formats::quote_for_message(content),
                                                       kMarkersHeader));
      header_seen = true;
      continue;
    }
    if (!formats::split_csv(line, fields)) formats::throw_line_error(name, n, "unterminated quote");
    if (fields.size() != 9)
      formats::throw_line_error(name, n, fmt::format("{} fields, expected 9 ({})", fields.size(), kMarkersHeader));
    Marker m;
    m.node = formats::field_text(fields[0]);
    m.name = formats::field_text(fields[1]);
    if (m.node.empty()) formats::throw_field_error(name, n, "node", fields[0], "is empty");
    if (m.name.empty()) formats::throw_field_error(name, n, "name", fields[1], "is empty");
    if (fields[2] != "realtime")
      formats::throw_field_error(name, n, "clock", fields[2], "is not realtime (markers are on CLOCK_REALTIME)");
    m.time = core::TimePoint::from_ns(core::Clock::realtime, formats::require_int64(name, n, "time_ns", fields[3]));
    m.source = read_stamp_source(name, n, fields[4]);
    m.key = formats::field_text(fields[5]);
    if (!fields[6].empty()) {
      m.sender_time =
          core::TimePoint::from_ns(core::Clock::realtime, formats::require_int64(name, n, "sender_ns", fields[6]));
      // The derived column must agree with the two it comes from: a hand-edited row shows here.
      if (!fields[7].empty() &&
          formats::require_int64(name, n, "sender_to_capture_ns", fields[7]) != m.time.ns() - m.sender_time->ns())
        formats::throw_field_error(name, n, "sender_to_capture_ns", fields[7], "is not time_ns - sender_ns");
    }
    m.origin = formats::field_text(fields[8]);
    out.push_back(std::move(m));
  }
  if (!header_seen)
    formats::throw_line_error(name, 0, fmt::format("no header: not an {} file", kMarkersFormat));
  return out;
}

std::vector<Marker> read_markers_file(const std::string& path) {
  const auto input = formats::InputText::read_file(path);
  return parse_markers_csv(input.text(), input.name());
}

}  // namespace m2mlat::markers
