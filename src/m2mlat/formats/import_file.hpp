// Importing a file by name, in a format given by the caller or detected from its content, and
// exporting events and pairs to a file by format.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/camera_latency.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/full_loop_csv.hpp"
#include "m2mlat/formats/imported.hpp"
#include "m2mlat/formats/pair_row.hpp"
#include "m2mlat/formats/pair_source.hpp"
#include "m2mlat/formats/pairs_export.hpp"
#include "m2mlat/formats/rig_paired.hpp"
#include "m2mlat/formats/rig_sync.hpp"

namespace m2mlat::formats {

struct ImportedFile {
  Format format = Format::events_csv;
  // EventImport for the event formats, PairedImport for rig_paired_csv, SyncImport for rig_sync_csv,
  // FullLoopImport for full_loop_csv, CameraLatencyImport for camera_latency (see content_of(format)).
  std::variant<EventImport, PairedImport, SyncImport, FullLoopImport, CameraLatencyImport> content;
};

// Imports `text` (named `name` in messages) as `format`, or as the detected format if none is
// given. Throws core::Error(data) for malformed or unrecognisable input (check_input's limits
// included: a line longer than 64 KiB, a last line cut mid-write), core::Error(usage) for a format
// m2mlat only writes. Nothing is returned unless the whole input is valid.
ImportedFile import_text(std::string_view text, std::string_view name, std::optional<Format> format,
                         const ImportOptions& options);
// The same for a file ("-" = standard input), read whole first. Also throws core::Error(no_input)
// if it does not exist and core::Error(io) if it cannot be read.
ImportedFile import_file(const std::string& path, std::optional<Format> format, const ImportOptions& options);

// The format of a file by the content of its first 64 KiB (detect_format), without reading it all;
// nullopt when unrecognised or unreadable (the import that follows names the problem). Not for
// standard input, which cannot be read twice.
std::optional<Format> detect_file_format(const std::string& path);

// The lean import of a file: timestamps only (CLOCK_REALTIME ns), per pin or label for the kernel
// log and the rig's export CSV (without building events), per "node/channel" for the other event
// formats and for the two sides of a paired CSV. `only_line` filters pins/labels (kernel log,
// export CSV). Throws core::Error(usage) for a sync-test CSV, which holds no timestamps.
std::vector<TimestampSeries> read_timestamps(const std::string& path, std::optional<Format> format,
                                             std::string_view only_line = {});

// Writes events as events_csv or events_jsonl to `path` ("-" = standard output), atomically.
// Throws core::Error(usage) for another format.
// options: the events' origins, the nodes' clock samples and steps, the CSV's meta lines
// (event_fields.hpp).
void export_events(const std::string& path, Format format, std::span<const core::Event> events,
                   const EventExportOptions& options = {});
// Writes pairs as pairs_csv, pairs_jsonl or rig_paired_csv (which has no names, uncertainty or
// flags: options only feed the other two), atomically, reading them a block at a time. Throws
// core::Error(usage) for another format.
void export_pairs(const std::string& path, Format format, const PairSource& pairs,
                  const PairExportOptions& options = {});
// The same for rows held whole, with options' per-pair columns (pair_rows_source.hpp).
void export_pairs(const std::string& path, Format format, std::span<const PairRow> pairs,
                  const PairExportOptions& options = {});

}  // namespace m2mlat::formats
