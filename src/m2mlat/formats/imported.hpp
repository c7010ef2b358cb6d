// What the event importers are told (which node and channel the events belong to, when the file
// does not say) and what they return.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/clock_records.hpp"

namespace m2mlat::formats {

struct ImportOptions {
  // Formats that name no node (kernel log, the rig's export CSV) put their events on this node.
  std::string node = "local";
  // Channel of those events. Empty: the format's default, "gpio<pin>" for a GPIO pin number and the
  // label itself for a non-numeric Line label. If given and the file holds several pins or labels,
  // `only_line` must choose one (two lines on one channel would mix their edges).
  std::string channel;
  // Keep only the records of this GPIO pin (kernel log) or Line label (export CSV); empty = all.
  // Records of other lines are counted in EventImport::skipped_lines.
  std::string only_line;
  // The edge recorded for formats that do not carry one. The reference rig's Hall sensors pull the
  // line low when the magnet passes, so its interrupts were on the falling edge.
  core::Edge edge = core::Edge::falling;
  // The reference rig's paired-results CSV: nodes and channels of its two columns.
  core::ChannelRef cause{"operator", "wheel"};
  core::ChannelRef effect{"vehicle", "wheel"};
};

// What the kernel-log importer knows of a record beyond the event (see kernel_log.hpp).
struct KernelLogRecord {
  std::uint32_t pin = 0;                    // the GPIO number the module printed
  std::int64_t time_ns = 0;                 // the module's timestamp: CLOCK_REALTIME ns since 1970
  std::optional<std::int64_t> log_time_us;  // the log's own stamp, us since boot ("[ s.us]" or kmsg)
  std::optional<std::uint64_t> kmsg_seq;    // /dev/kmsg record sequence number, if the line had one
  friend bool operator==(const KernelLogRecord&, const KernelLogRecord&) = default;
};

// The result of importing a file of events (kernel log, export CSV, generic events CSV/JSONL).
struct EventImport {
  std::vector<core::Event> events;  // in file order
  // Kernel log only: one record per event (same index), with the kmsg sequence number and the log's
  // own timestamp; empty for other formats.
  std::vector<KernelLogRecord> kernel_records;
  // m2mlat's events files: the clock samples and steps carried beside the events (clock_records.hpp),
  // in file order; empty for other formats and for files written without them.
  std::vector<ClockRecord> clock_records;
  std::size_t records = 0;        // data lines read (header, comments and blank lines excluded)
  std::size_t ignored_lines = 0;  // kernel log: unrelated log lines passed over
  std::size_t skipped_lines = 0;  // records of other pins/labels left out by ImportOptions::only_line
};

// The lean import: only the timestamps, per GPIO pin or line label, without building events.
struct TimestampSeries {
  std::string label;             // the pin number ("16") or Line label as written in the file
  std::vector<std::int64_t> ns;  // CLOCK_REALTIME ns since 1970, in file order
  // Kernel log: the log's own stamp of each line (us since boot, CLOCK_MONOTONIC), parallel to ns
  // when every line of the series had one, else empty.
  std::vector<std::int64_t> log_time_us;
};

}  // namespace m2mlat::formats
