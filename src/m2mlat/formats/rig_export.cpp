// Reading the reference rig's Line,Seconds,Nanoseconds export CSV.
#include "m2mlat/formats/rig_export.hpp"

#include <charconv>
#include <string>

#include "m2mlat/formats/fixed_csv.hpp"
#include "m2mlat/formats/line_selection.hpp"

namespace m2mlat::formats {

namespace {
enum ExportColumn : std::size_t { kLine = 0, kSeconds = 1, kNanoseconds = 2 };

void check_label(const FixedCsv& csv) {
  if (csv.text(kLine).empty()) csv.fail("field Line: is empty");
}

// Whether Line counts the rows (0, 1, 2 ... or 1, 2, 3 ...), as the rig's export.sh writes it.
bool line_counts_rows(std::string_view text, std::string_view name) {
  FixedCsv csv(text, name, kRigExportColumns);
  long row = 0, first = -1;
  while (csv.next()) {
    long value = -1;
    const auto label = csv.text(kLine);
    const auto [end, ec] = std::from_chars(label.data(), label.data() + label.size(), value);
    if (ec != std::errc{} || end != label.data() + label.size()) return false;
    if (row == 0) first = value;
    if ((first != 0 && first != 1) || value != first + row) return false;
    ++row;
  }
  return row >= 2;
}

// The pin of "<name>_measuremest_<pin>.csv" (export.sh's spelling; "measurement" too), or empty.
std::string pin_from_name(std::string_view name) {
  const auto slash = name.find_last_of('/');
  std::string_view base = slash == std::string_view::npos ? name : name.substr(slash + 1);
  if (base.ends_with(".csv")) base.remove_suffix(4);
  const auto underscore = base.find_last_of('_');
  if (underscore == std::string_view::npos) return {};
  const auto pin = base.substr(underscore + 1), before = base.substr(0, underscore);
  if (pin.empty() || pin.find_first_not_of("0123456789") != std::string_view::npos) return {};
  if (!before.ends_with("_measuremest") && !before.ends_with("_measurement")) return {};
  return std::string(pin);
}

}  // namespace

std::string rig_export_line_label(std::string_view text, std::string_view name) {
  if (!line_counts_rows(text, name)) return {};
  const auto pin = pin_from_name(name);
  return pin.empty() ? std::string("line") : pin;
}

EventImport import_rig_export_csv(std::string_view text, std::string_view name,
                                  const ImportOptions& options) {
  if (options.node.empty()) throw_line_error(name, 0, "no node given for its events");
  FixedCsv csv(text, name, kRigExportColumns);
  LineSelection selection(options, name);
  const std::string counted = rig_export_line_label(text, name);
  EventImport result;
  result.events.reserve(count_lines(text));
  core::Event event;
  event.node = options.node;
  event.edge = options.edge;
  event.flags = core::kFlagImported | core::kFlagNoKernelSeqno;
  while (csv.next()) {
    ++result.records;
    check_label(csv);
    const std::int64_t ns = csv.epoch_ns(kSeconds, kNanoseconds);
    const std::string* channel =
        selection.channel_for(counted.empty() ? csv.text(kLine) : std::string_view(counted), csv.line(), "Line");
    if (channel == nullptr) {
      ++result.skipped_lines;
      continue;
    }
    if (event.channel != *channel) event.channel = *channel;
    event.time = core::TimePoint::from_ns(core::Clock::realtime, ns);
    result.events.push_back(event);
  }
  return result;
}

std::vector<TimestampSeries> scan_rig_export_timestamps(std::string_view text, std::string_view name,
                                                        std::string_view only_line) {
  const std::string_view wanted = canonical_label(trim(only_line));
  const std::string counted = rig_export_line_label(text, name);
  FixedCsv csv(text, name, kRigExportColumns);
  std::vector<TimestampSeries> series;
  std::size_t last = 0;
  while (csv.next()) {
    check_label(csv);
    const std::int64_t ns = csv.epoch_ns(kSeconds, kNanoseconds);
    const std::string_view label = counted.empty() ? canonical_label(csv.text(kLine)) : std::string_view(counted);
    if (series.empty() || series[last].label != label) {
      if (!wanted.empty() && label != wanted) continue;
      last = series.size();
      for (std::size_t i = 0; i < series.size(); ++i)
        if (series[i].label == label) last = i;
      if (last == series.size()) series.push_back({std::string(label), {}, {}});
    }
    series[last].ns.push_back(ns);
  }
  return series;
}

}  // namespace m2mlat::formats
