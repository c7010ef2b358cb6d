// Kernel-log lines of the reference rig's GPIO interrupt module: GPIO_<pin>_IRQ:<ns>.
//
// The module printed, from its interrupt handler, the CLOCK_REALTIME nanoseconds of the edge with
// printk, e.g. "GPIO_16_IRQ:1762872545550296135". Such lines are read as plain lines, inside
// `dmesg` output (with or without the "[ 1234.567890] " prefix, `dmesg -T` dates, other log lines
// mixed in) and as /dev/kmsg records ("6,1234,5678901,-;GPIO_16_IRQ:..."), whose sequence number is
// kept. A line that carries the marker GPIO_<something>_IRQ: but not a valid pin and timestamp is an
// error naming file:line; every other line is counted and passed over.
//
// parse_kernel_log_line() looks at one line and allocates nothing: the live /dev/kmsg capture uses
// it record by record; the importers below use it over a whole file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/formats/imported.hpp"

namespace m2mlat::formats {

enum class KernelLineKind : std::uint8_t {
  unrelated = 0,  // no GPIO_<pin>_IRQ: marker: another kernel message, a blank or continuation line
  record = 1,     // a valid GPIO record
  malformed = 2,  // the marker is there, but the pin, the timestamp or the kmsg header is not valid
};

struct KernelLogLine {
  KernelLineKind kind = KernelLineKind::unrelated;
  KernelLogRecord record;     // kind == record
  std::string_view pin_text;  // kind == record: the pin as written (a view into the line)
  // kind == malformed: the part at fault ("pin", "timestamp", "kmsg header"), its text (a view into
  // the line) and what is wrong with it.
  std::string_view field;
  std::string_view text;
  std::string_view problem;

  // "field timestamp: '12ab' is not an integer number of nanoseconds" (malformed lines).
  std::string describe() const;
};

// Classifies and parses one line (with or without its newline). The marker is looked for anywhere
// in the line, after whatever prefix; the timestamp must run to the end of the line. A /dev/kmsg
// header in front ("<priority>,<seq>,<us since boot>,<flags>[,...];") gives kmsg_seq and
// log_time_us; a dmesg "[ seconds.micro]" prefix gives log_time_us.
KernelLogLine parse_kernel_log_line(std::string_view line);

// Imports every GPIO record of a kernel log as events of ImportOptions::node, channel "gpio<pin>"
// (or ImportOptions::channel), edge ImportOptions::edge, clock realtime, flags imported and
// no-kernel-seqno (the module printed no GPIO sequence numbers; the kmsg sequence number counts all
// log messages, not edges, and is kept in EventImport::kernel_records instead). `name` is the file
// name for messages. Throws core::Error(data) for a malformed GPIO line, an empty input, or an
// input without any GPIO record (of ImportOptions::only_line, if given).
EventImport import_kernel_log(std::string_view text, std::string_view name, const ImportOptions& options);

// The lean import: the timestamps per pin, in order of first appearance, without events (with the
// log's own stamps when every line had one: TimestampSeries::log_time_us). Same
// checks and errors as import_kernel_log. `only_line` (a pin number, or empty for all) filters.
std::vector<TimestampSeries> scan_kernel_log_timestamps(std::string_view text, std::string_view name,
                                                        std::string_view only_line = {});
// The same from a file ("-" = standard input), read block by block (file_lines.hpp): the same
// series and the same errors as InputText::read_file + check_input + scan_kernel_log_timestamps,
// without the whole file in memory.
std::vector<TimestampSeries> read_kernel_log_timestamps(const std::string& path, std::string_view only_line = {});

}  // namespace m2mlat::formats
