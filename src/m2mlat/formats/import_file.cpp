// Dispatch of imports and exports by format, and file handling around them.
#include "m2mlat/formats/import_file.hpp"

#include <fmt/format.h>

#include <fstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/formats/events_csv.hpp"
#include "m2mlat/formats/events_jsonl.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/kernel_log.hpp"
#include "m2mlat/formats/output_text.hpp"
#include "m2mlat/formats/pair_rows_source.hpp"
#include "m2mlat/formats/rig_export.hpp"

namespace m2mlat::formats {

namespace {

[[noreturn]] void throw_not_importable(std::string_view name, Format format) {
  throw core::Error(
      core::ErrorKind::usage,
      fmt::format("{}: is a {} file, which m2mlat writes for other programs but does not import; "
                  "import the events the pairs were made from",
                  name, to_string(format)));
}

// Appends `ns` to the series labelled `label`, creating it on first use.
void add_to_series(std::vector<TimestampSeries>& series, const std::string& label, std::int64_t ns) {
  for (TimestampSeries& s : series) {
    if (s.label == label) {
      s.ns.push_back(ns);
      return;
    }
  }
  series.push_back({label, {ns}, {}});
}

void add_events(std::vector<TimestampSeries>& series, const std::vector<core::Event>& events) {
  std::string label;
  for (const core::Event& event : events) {
    label = event.node + "/" + event.channel;
    add_to_series(series, label, event.time.ns());
  }
}

}  // namespace

ImportedFile import_text(std::string_view text, std::string_view name, std::optional<Format> format,
                         const ImportOptions& options) {
  check_input(text, name);
  const Format chosen = format ? *format : require_format(text, name);
  ImportedFile result;
  result.format = chosen;
  switch (chosen) {
    case Format::kernel_log: result.content = import_kernel_log(text, name, options); break;
    case Format::rig_export_csv: result.content = import_rig_export_csv(text, name, options); break;
    case Format::rig_paired_csv: result.content = import_rig_paired_csv(text, name, options); break;
    case Format::rig_sync_csv: result.content = import_rig_sync_csv(text, name); break;
    case Format::events_csv: result.content = import_events_csv(text, name, options); break;
    case Format::events_jsonl: result.content = import_events_jsonl(text, name, options); break;
    case Format::full_loop_csv: result.content = import_full_loop_csv(text, name); break;
    case Format::camera_latency: result.content = import_camera_latency(text, name); break;
    case Format::pairs_csv:
    case Format::pairs_jsonl: throw_not_importable(name, chosen);
  }
  return result;
}

ImportedFile import_file(const std::string& path, std::optional<Format> format,
                         const ImportOptions& options) {
  const InputText input = InputText::read_file(path);
  return import_text(input.text(), input.name(), format, options);
}

std::optional<Format> detect_file_format(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(64 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return detect_format(head);
}

std::vector<TimestampSeries> read_timestamps(const std::string& path, std::optional<Format> format,
                                             std::string_view only_line) {
  // A kernel log is read block by block (file_lines.hpp): 8 or 16 bytes an edge instead of ~50.
  if (format == Format::kernel_log) return read_kernel_log_timestamps(path, only_line);
  const InputText input = InputText::read_file(path);
  check_input(input.text(), input.name());
  const Format chosen = format ? *format : require_format(input.text(), input.name());
  std::vector<TimestampSeries> series;
  switch (chosen) {
    case Format::kernel_log: return scan_kernel_log_timestamps(input.text(), input.name(), only_line);
    case Format::rig_export_csv: return scan_rig_export_timestamps(input.text(), input.name(), only_line);
    case Format::events_csv:
      add_events(series, import_events_csv(input.text(), input.name(), {}).events);
      break;
    case Format::events_jsonl:
      add_events(series, import_events_jsonl(input.text(), input.name(), {}).events);
      break;
    case Format::rig_paired_csv: {
      const ImportOptions options;
      const PairedImport paired = import_rig_paired_csv(input.text(), input.name(), options);
      TimestampSeries causes{core::to_string(options.cause), {}, {}};
      TimestampSeries effects{core::to_string(options.effect), {}, {}};
      for (const PairRow& pair : paired.pairs) {
        causes.ns.push_back(pair.cause_time.ns());
        effects.ns.push_back(pair.effect_time.ns());
      }
      series.push_back(std::move(causes));
      series.push_back(std::move(effects));
      break;
    }
    case Format::rig_sync_csv:
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: a sync-test CSV holds offsets, not event timestamps", input.name()));
    case Format::full_loop_csv:
    case Format::camera_latency:
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: a {} file is summarised by `m2mlat stats` and `m2mlat report`, "
                                    "not paired from its timestamps",
                                    input.name(), to_string(chosen)));
    case Format::pairs_csv:
    case Format::pairs_jsonl: throw_not_importable(input.name(), chosen);
  }
  return series;
}

void export_events(const std::string& path, Format format, std::span<const core::Event> events,
                   const EventExportOptions& options) {
  if (format != Format::events_csv && format != Format::events_jsonl)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("events cannot be exported as {} (use events-csv or events-jsonl)", to_string(format)));
  core::write_output_file(path, [&](std::ostream& out) {
    if (format == Format::events_csv)
      write_events_csv(out, events, options);
    else
      write_events_jsonl(out, events, options);
  });
}

void export_pairs(const std::string& path, Format format, const PairSource& pairs,
                  const PairExportOptions& options) {
  if (format != Format::pairs_csv && format != Format::pairs_jsonl && format != Format::rig_paired_csv)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("pairs cannot be exported as {} (use pairs-csv, pairs-jsonl or rig-paired-csv)",
                    to_string(format)));
  core::write_output_file(path, [&](std::ostream& out) {
    if (format == Format::pairs_csv)
      write_pairs_csv(out, pairs, options);
    else if (format == Format::pairs_jsonl)
      write_pairs_jsonl(out, pairs, options);
    else
      write_rig_paired_csv(out, pairs);
  });
}

void export_pairs(const std::string& path, Format format, std::span<const PairRow> pairs,
                  const PairExportOptions& options) {
  export_pairs(path, format, PairRowsSource(pairs, options), options);
}

}  // namespace m2mlat::formats
