// Parsing GPIO_<pin>_IRQ:<ns> kernel-log lines, alone or over a whole file.
#include "m2mlat/formats/kernel_log.hpp"

#include <fmt/format.h>

#include <limits>

#include "m2mlat/core/number.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/file_lines.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/line_selection.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::string_view kMarkerStart = "GPIO_";
constexpr std::string_view kMarkerEnd = "_IRQ";

void set_malformed(KernelLogLine& out, std::string_view field, std::string_view text,
                   std::string_view problem) {
  out.kind = KernelLineKind::malformed;
  out.field = field;
  out.text = text;
  out.problem = problem;
}

// Finds "GPIO_<token>_IRQ:" with no space inside the token. Sets `pin` to the token and returns the
// position of the marker, or npos when the line has none.
std::size_t find_marker(std::string_view line, std::string_view& pin, std::size_t& colon) {
  std::size_t from = 0;
  for (;;) {
    const std::size_t pos = line.find(kMarkerStart, from);
    if (pos == std::string_view::npos) return pos;
    const std::size_t begin = pos + kMarkerStart.size();
    std::size_t end = begin;
    while (end < line.size() && line[end] != ':' && line[end] != ' ' && line[end] != '\t') ++end;
    if (end < line.size() && line[end] == ':' && end - begin >= kMarkerEnd.size() &&
        line.substr(end - kMarkerEnd.size(), kMarkerEnd.size()) == kMarkerEnd) {
      pin = line.substr(begin, end - kMarkerEnd.size() - begin);
      colon = end;
      return pos;
    }
    from = begin;
  }
}

// Reads the /dev/kmsg header "<priority>,<seq>,<us>,<flags>[,...]" (the part before ';').
bool parse_kmsg_header(std::string_view header, KernelLogRecord& record) {
  std::string_view parts[4];
  for (int i = 0; i < 4; ++i) {
    const std::size_t comma = header.find(',');
    if (comma == std::string_view::npos && i < 3) return false;
    parts[i] = header.substr(0, comma);
    header = comma == std::string_view::npos ? std::string_view{} : header.substr(comma + 1);
  }
  std::uint64_t priority = 0;
  std::uint64_t seq = 0;
  std::int64_t us = 0;
  if (!core::parse_integer(parts[0], priority) || !core::parse_integer(parts[1], seq) ||
      !is_digits(parts[2]) || !core::parse_integer(parts[2], us) || parts[3].empty())
    return false;
  record.kmsg_seq = seq;
  record.log_time_us = us;
  return true;
}

// The dmesg "[ 1234.567890]" stamp anywhere in the prefix (dmesg, /var/log/kern.log), in us. Other
// brackets (dmesg -T dates) give nothing: they are not an error. Written out rather than through
// core::parse_seconds because it runs on every line of a log.
void parse_dmesg_stamp(std::string_view prefix, KernelLogRecord& record) {
  const std::size_t open = prefix.find('[');
  if (open == std::string_view::npos) return;
  const std::size_t close = prefix.find(']', open);
  if (close == std::string_view::npos) return;
  const std::string_view inside = trim(prefix.substr(open + 1, close - open - 1));
  const std::size_t dot = inside.find('.');
  const std::string_view whole_text = inside.substr(0, dot);
  const std::string_view frac_text =
      dot == std::string_view::npos ? std::string_view{} : inside.substr(dot + 1);
  std::uint64_t whole = 0;
  std::uint64_t frac = 0;
  if (!core::parse_integer(whole_text, whole) || whole > 9'000'000'000'000u || frac_text.size() > 9 ||
      (!frac_text.empty() && !core::parse_integer(frac_text, frac)) ||
      (dot != std::string_view::npos && frac_text.empty()))
    return;
  // Scale the fraction to microseconds: dmesg prints 6 digits; fewer are padded, more truncated.
  for (std::size_t digits = frac_text.size(); digits < 6; ++digits) frac *= 10;
  for (std::size_t digits = frac_text.size(); digits > 6; --digits) frac /= 10;
  record.log_time_us = static_cast<std::int64_t>(whole * 1'000'000 + frac);
}

}  // namespace

std::string KernelLogLine::describe() const {
  return fmt::format("field {}: {} {}", field, quote_for_message(text), problem);
}

// Every path returns the one `out`, so that it is built in the caller's storage (named return value
// optimisation): copying the struct out was a third of the time of this function, which runs on
// every line of a log.
KernelLogLine parse_kernel_log_line(std::string_view line) {
  KernelLogLine out;
  while (!line.empty() &&
         (line.back() == '\n' || line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
    line.remove_suffix(1);
  std::string_view pin;
  std::size_t colon = 0;
  const std::size_t marker = find_marker(line, pin, colon);
  if (marker == std::string_view::npos) return out;  // unrelated

  // core::parse_integer into an unsigned type takes digits only (no sign, no space): one pass each.
  std::uint64_t pin_number = 0;
  const std::string_view value = line.substr(colon + 1);
  std::uint64_t ns = 0;
  if (!core::parse_integer(pin, pin_number) || pin_number > std::numeric_limits<std::uint32_t>::max()) {
    set_malformed(out, "pin", pin, "is not a GPIO number");
  } else if (!core::parse_integer(value, ns) ||
             ns > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    if (value.empty())
      set_malformed(out, "timestamp", value, "is empty");
    else if (!is_digits(value))
      set_malformed(out, "timestamp", value, "is not an integer number of nanoseconds");
    else
      set_malformed(out, "timestamp", value, "is out of range (more than 2^63-1 ns)");
  } else {
    out.kind = KernelLineKind::record;
    out.record.time_ns = static_cast<std::int64_t>(ns);
    out.record.pin = static_cast<std::uint32_t>(pin_number);
    out.pin_text = pin;
    const std::string_view prefix = line.substr(0, marker);
    const std::size_t semicolon = prefix.find(';');
    if (!prefix.empty() && prefix.front() >= '0' && prefix.front() <= '9' &&
        semicolon != std::string_view::npos) {
      const std::string_view header = prefix.substr(0, semicolon);
      if (!parse_kmsg_header(header, out.record))
        set_malformed(out, "kmsg header", header, "is not 'priority,sequence,microseconds,flags'");
    } else {
      parse_dmesg_stamp(prefix, out.record);
    }
  }
  return out;
}

namespace {

struct ScanCounts {
  std::size_t records = 0;
  std::size_t ignored = 0;
  std::size_t lines = 0;
};

// Runs `on_record(parsed, line_number)` for every GPIO record of the lines `reader` gives (a
// LineReader over a whole text, or FileLines); throws for malformed ones.
template <class Reader, class OnRecord>
ScanCounts scan(Reader& reader, std::string_view name, OnRecord&& on_record) {
  ScanCounts counts;
  std::string_view line;
  while (reader.next(line)) {
    const KernelLogLine parsed = parse_kernel_log_line(line);
    if (parsed.kind == KernelLineKind::record) {
      ++counts.records;
      on_record(parsed, reader.line_number());
    } else if (parsed.kind == KernelLineKind::malformed) {
      const long at = reader.line_number();
      std::string what = parsed.describe();  // before the line's buffer is read into again
      // A file read block by block: the checks of the whole file (line lengths, a cut last line)
      // come first, as they do when it is read whole.
      if constexpr (requires { reader.read_to_end(); }) reader.read_to_end();
      throw_line_error(name, at, what);
    } else if (!is_blank(line)) {
      ++counts.ignored;
    }
  }
  counts.lines = static_cast<std::size_t>(reader.line_number());
  if (counts.lines == 0) throw_line_error(name, 0, "is empty");
  if (counts.records == 0)
    throw_line_error(name, 0,
                     fmt::format("has no GPIO_<pin>_IRQ:<ns> lines ({} other lines); is it a kernel log?",
                                 counts.ignored));
  return counts;
}

[[noreturn]] void throw_nothing_selected(std::string_view name, std::string_view only_line,
                                         std::size_t records) {
  throw_line_error(
      name, 0, fmt::format("none of its {} GPIO records is on pin {}", records, canonical_label(only_line)));
}

}  // namespace

EventImport import_kernel_log(std::string_view text, std::string_view name, const ImportOptions& options) {
  if (options.node.empty()) throw_line_error(name, 0, "no node given for its events");
  EventImport result;
  result.events.reserve(count_lines(text));
  result.kernel_records.reserve(result.events.capacity());
  LineSelection selection(options, name);
  core::Event event;
  event.node = options.node;
  event.edge = options.edge;
  event.flags = core::kFlagImported | core::kFlagNoKernelSeqno;
  LineReader reader(text);
  const ScanCounts counts = scan(reader, name, [&](const KernelLogLine& parsed, long line) {
    const std::string* channel = selection.channel_for(parsed.pin_text, line, "pin");
    if (channel == nullptr) {
      ++result.skipped_lines;
      return;
    }
    if (event.channel != *channel) event.channel = *channel;
    event.time = core::TimePoint::from_ns(core::Clock::realtime, parsed.record.time_ns);
    result.events.push_back(event);
    result.kernel_records.push_back(parsed.record);
  });
  result.records = counts.records;
  result.ignored_lines = counts.ignored;
  if (result.events.empty()) throw_nothing_selected(name, options.only_line, counts.records);
  if (result.events.capacity() > 2 * result.events.size() + 1024) {  // a log mostly of other lines
    result.events.shrink_to_fit();
    result.kernel_records.shrink_to_fit();
  }
  return result;
}

namespace {

// The lean import over any line reader; `expected_lines`: what to reserve for the first series.
template <class Reader>
std::vector<TimestampSeries> scan_timestamps(Reader& reader, std::string_view name, std::string_view only_line,
                                             std::size_t expected_lines) {
  const std::string_view wanted = canonical_label(trim(only_line));
  std::vector<TimestampSeries> series;
  std::size_t last = 0;
  std::size_t kept = 0;
  bool all_stamped = true;  // every kept line had the log's own stamp
  const ScanCounts counts = scan(reader, name, [&](const KernelLogLine& parsed, long) {
    const std::string_view pin = canonical_label(parsed.pin_text);
    if (series.empty() || series[last].label != pin) {
      if (!wanted.empty() && pin != wanted) return;
      last = series.size();
      for (std::size_t i = 0; i < series.size(); ++i)
        if (series[i].label == pin) last = i;
      if (last == series.size()) {
        series.push_back({std::string(pin), {}, {}});
        if (last == 0) {
          // Both columns at once: the log's stamps grew by doubling, copying as they went.
          series.front().ns.reserve(expected_lines);
          series.front().log_time_us.reserve(expected_lines);
        }
      }
    }
    series[last].ns.push_back(parsed.record.time_ns);
    if (parsed.record.log_time_us && all_stamped)
      series[last].log_time_us.push_back(*parsed.record.log_time_us);
    else
      all_stamped = false;
    ++kept;
  });
  if (kept == 0) throw_nothing_selected(name, only_line, counts.records);
  if (!all_stamped)
    for (auto& s : series) std::vector<std::int64_t>().swap(s.log_time_us);
  return series;
}

}  // namespace

std::vector<TimestampSeries> scan_kernel_log_timestamps(std::string_view text, std::string_view name,
                                                        std::string_view only_line) {
  LineReader reader(text);
  return scan_timestamps(reader, name, only_line, count_lines(text));
}

std::vector<TimestampSeries> read_kernel_log_timestamps(const std::string& path, std::string_view only_line) {
  FileLines lines(path);
  // Reserved, not touched: pages a shorter estimate leaves unused cost address space only. 32 bytes
  // is the module's bare line ("GPIO_16_IRQ:1762872545550296135\n"); lines with a dmesg or kmsg
  // prefix are longer, and a log of shorter lines grows the columns as it goes.
  return scan_timestamps(lines, lines.name(), only_line, lines.size_hint() / 32 + 16);
}

}  // namespace m2mlat::formats
