// The file formats m2mlat reads and writes, their names, and telling them apart by content.
//
// Detection looks at the first line that is not blank: a known CSV header, a "# format:" marker, a
// JSON object with a "format" member; failing those, a kernel log is recognised by a
// GPIO_<pin>_IRQ: line anywhere in the text (dmesg output starts with boot messages).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace m2mlat::formats {

// Values may be stored by name only: the names are the stable part.
enum class Format : std::uint8_t {
  kernel_log,      // GPIO_<pin>_IRQ:<ns> lines: plain, dmesg, /dev/kmsg        (import)
  rig_export_csv,  // reference rig: Line,Seconds,Nanoseconds                   (import)
  rig_paired_csv,  // reference rig: remote_station_s,...,,m2m_latency_ms        (import, export of pairs)
  rig_sync_csv,    // reference rig: trigger_time_s,sync_offset_ns,Jitter_ns,... (import)
  events_csv,      // m2mlat-events/2 as CSV                                     (import, export)
  events_jsonl,    // m2mlat-events/2 as JSON Lines                              (import, export)
  pairs_csv,       // m2mlat-pairs/4 as CSV                                      (export)
  pairs_jsonl,     // m2mlat-pairs/4 as JSON Lines                               (export)
  full_loop_csv,   // full-loop rig: VEHICLE_GY_ON,...,PHOTOTRANSISTOR           (stats, report)
  camera_latency,  // full-loop rig's camera-to-monitor file: LATENCY (ms)      (stats, report)
};

inline constexpr std::array<Format, 10> kAllFormats{
    Format::kernel_log,    Format::rig_export_csv, Format::rig_paired_csv, Format::rig_sync_csv,
    Format::events_csv,    Format::events_jsonl,   Format::pairs_csv,      Format::pairs_jsonl,
    Format::full_loop_csv, Format::camera_latency};

// "kernel-log", "rig-export-csv", "rig-paired-csv", "rig-sync-csv", "events-csv", "events-jsonl",
// "pairs-csv", "pairs-jsonl", "full-loop-csv", "camera-latency".
std::string_view to_string(Format format);
// Parses those names; throws core::Error(usage) listing them otherwise.
Format parse_format(std::string_view name);

// What an import yields for a format: events, pairs (with their events), sync-test samples, the
// full-loop rig's per-event timestamps, or glass-to-glass latencies.
enum class Content : std::uint8_t { events, pairs, sync_samples, full_loop, latencies };
Content content_of(Format format);
// True for the formats m2mlat can import into a store (the pairs exports are for other programs;
// the full-loop files are read by `stats` and `report` only).
bool is_importable(Format format);

// The format of `text` by its content, or nullopt if it is none of them.
std::optional<Format> detect_format(std::string_view text);
// The same, but throws core::Error(data) naming `name` and quoting the first line when unknown,
// or saying the input is empty.
Format require_format(std::string_view text, std::string_view name);

}  // namespace m2mlat::formats
