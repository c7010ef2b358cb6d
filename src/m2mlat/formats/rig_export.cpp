// Reading the reference rig's Line,Seconds,Nanoseconds export CSV.
#include "m2mlat/formats/rig_export.hpp"

#include "m2mlat/formats/fixed_csv.hpp"
#include "m2mlat/formats/line_selection.hpp"

namespace m2mlat::formats {

namespace {
enum ExportColumn : std::size_t { kLine = 0, kSeconds = 1, kNanoseconds = 2 };

void check_label(const FixedCsv& csv) {
  if (csv.text(kLine).empty()) csv.fail("field Line: is empty");
}
}  // namespace

EventImport import_rig_export_csv(std::string_view text, std::string_view name,
                                  const ImportOptions& options) {
  if (options.node.empty()) throw_line_error(name, 0, "no node given for its events");
  FixedCsv csv(text, name, kRigExportColumns);
  LineSelection selection(options, name);
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
    const std::string* channel = selection.channel_for(csv.text(kLine), csv.line(), "Line");
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
  FixedCsv csv(text, name, kRigExportColumns);
  std::vector<TimestampSeries> series;
  std::size_t last = 0;
  while (csv.next()) {
    check_label(csv);
    const std::int64_t ns = csv.epoch_ns(kSeconds, kNanoseconds);
    const std::string_view label = canonical_label(csv.text(kLine));
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
