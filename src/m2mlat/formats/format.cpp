// Format names and detection by content.
#include "m2mlat/formats/format.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/camera_latency.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/full_loop_csv.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/kernel_log.hpp"
#include "m2mlat/formats/rig_export.hpp"
#include "m2mlat/formats/rig_paired.hpp"
#include "m2mlat/formats/rig_sync.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::array<std::string_view, kAllFormats.size()> kNames{
    "kernel-log",   "rig-export-csv", "rig-paired-csv", "rig-sync-csv",  "events-csv",
    "events-jsonl", "pairs-csv",      "pairs-jsonl",    "full-loop-csv", "camera-latency"};

constexpr std::string_view kPairsFamily = "m2mlat-pairs/";

bool same_columns(const std::vector<std::string_view>& fields, std::span<const std::string_view> columns) {
  if (fields.size() != columns.size()) return false;
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (fields[i] != columns[i]) return false;
  return true;
}

// The format named by a "format:" marker (CSV comment or JSON member), if it is one of ours.
std::optional<Format> from_marker(std::string_view marker, Format events, Format pairs) {
  if (marker.starts_with(kEventsFormatFamily)) return events;
  if (marker.starts_with(kPairsFamily)) return pairs;
  return std::nullopt;
}

std::optional<Format> from_header(std::string_view line) {
  std::vector<std::string_view> fields;
  if (!split_csv(line, fields)) return std::nullopt;
  if (same_columns(fields, kRigExportColumns)) return Format::rig_export_csv;
  if (same_columns(fields, kRigPairedColumns)) return Format::rig_paired_csv;
  if (same_columns(fields, kRigSyncColumns)) return Format::rig_sync_csv;
  if (looks_like_full_loop_header(fields)) return Format::full_loop_csv;
  if (fields.size() == 1 && fields[0] == kCameraLatencyHeader) return Format::camera_latency;
  // m2mlat-pairs/3 and /4 start with scenario,session,label; /2 with cause_node.
  for (const std::string_view field : fields)
    if (field == "cause_node") return Format::pairs_csv;
  bool node = false;
  bool time = false;
  for (const std::string_view field : fields) {
    const std::string text = field_text(field);
    node = node || text == "node";
    time = time || text == "time_ns" || text == "time_s";
  }
  if (node && time) return Format::events_csv;
  return std::nullopt;
}

// A kernel log: any line with the GPIO_<pin>_IRQ: marker (a malformed one too: the importer then
// names it). Only lines holding "GPIO_" are looked at, so this is a quick search.
bool has_kernel_record(std::string_view text) {
  std::size_t from = 0;
  for (;;) {
    const std::size_t pos = text.find("GPIO_", from);
    if (pos == std::string_view::npos) return false;
    const std::size_t begin = text.rfind('\n', pos);
    const std::size_t start = begin == std::string_view::npos ? 0 : begin + 1;
    const std::size_t end = text.find('\n', pos);
    const std::string_view line = text.substr(start, end == std::string_view::npos ? text.npos : end - start);
    if (parse_kernel_log_line(line).kind != KernelLineKind::unrelated) return true;
    if (end == std::string_view::npos) return false;
    from = end;
  }
}

}  // namespace

std::string_view to_string(Format format) { return kNames.at(static_cast<std::size_t>(format)); }

Format parse_format(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return kAllFormats[i];
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("unknown format '{}' (expected one of: {})", name, fmt::join(kNames, ", ")));
}

Content content_of(Format format) {
  switch (format) {
    case Format::rig_paired_csv:
    case Format::pairs_csv:
    case Format::pairs_jsonl: return Content::pairs;
    case Format::rig_sync_csv: return Content::sync_samples;
    case Format::full_loop_csv: return Content::full_loop;
    case Format::camera_latency: return Content::latencies;
    default: return Content::events;
  }
}

bool is_importable(Format format) {
  return format != Format::pairs_csv && format != Format::pairs_jsonl && format != Format::full_loop_csv &&
         format != Format::camera_latency;
}

std::optional<Format> detect_format(std::string_view text) {
  LineReader reader(text);
  std::string_view line;
  for (;;) {
    if (!reader.next(line)) return std::nullopt;
    line = trim(line);
    if (line.empty()) continue;
    if (line.front() != '#') break;
    // A comment first: our CSV's "# format:" marker, or a comment before an events CSV header.
    const std::string_view body = trim(line.substr(1));
    if (body.starts_with("format:")) {
      if (auto format = from_marker(trim(body.substr(7)), Format::events_csv, Format::pairs_csv))
        return format;
      break;
    }
  }
  if (line.front() == '{') {
    const auto json = nlohmann::json::parse(line, nullptr, false);
    if (!json.is_discarded() && json.is_object()) {
      const auto found = json.find("format");
      if (found != json.end() && found->is_string())
        if (auto format =
                from_marker(found->get_ref<const std::string&>(), Format::events_jsonl, Format::pairs_jsonl))
          return format;
    }
  } else if (auto format = from_header(line)) {
    return format;
  }
  if (has_kernel_record(text)) return Format::kernel_log;
  return std::nullopt;
}

Format require_format(std::string_view text, std::string_view name) {
  if (auto format = detect_format(text)) return *format;
  LineReader reader(text);
  std::string_view line;
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    throw_line_error(
        name, reader.line_number(),
        fmt::format("cannot tell the format from {}: expected a kernel log (GPIO_<pin>_IRQ:<ns> "
                    "lines), a CSV header of the reference rig, of the full-loop rig or of m2mlat, "
                    "a 'LATENCY (ms)' header, or m2mlat JSON Lines; "
                    "name the format (one of: {})",
                    quote_for_message(line), fmt::join(kNames, ", ")));
  }
  throw_line_error(name, 0, "is empty");
}

}  // namespace m2mlat::formats
