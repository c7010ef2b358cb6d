// Reading and writing the reference rig's paired-results CSV.
#include "m2mlat/formats/rig_paired.hpp"

#include "m2mlat/formats/fixed_csv.hpp"
#include "m2mlat/formats/output_text.hpp"
#include "m2mlat/formats/pair_rows_source.hpp"

namespace m2mlat::formats {

namespace {
enum PairedColumn : std::size_t {
  kRemoteS = 0,
  kRemoteNs = 1,
  kVehicleS = 2,
  kVehicleNs = 3,
  kEmpty = 4,
  kLatency = 5
};

core::Event make_event(const core::ChannelRef& where, core::Edge edge) {
  core::Event event;
  event.node = where.node;
  event.channel = where.channel;
  event.edge = edge;
  event.flags = core::kFlagImported | core::kFlagNoKernelSeqno;
  return event;
}
}  // namespace

PairedImport import_rig_paired_csv(std::string_view text, std::string_view name,
                                   const ImportOptions& options) {
  if (options.cause.node.empty() || options.cause.channel.empty() || options.effect.node.empty() ||
      options.effect.channel.empty())
    throw_line_error(name, 0, "no node or channel given for its cause or effect events");
  FixedCsv csv(text, name, kRigPairedColumns);
  PairedImport result;
  core::Event cause = make_event(options.cause, options.edge);
  core::Event effect = make_event(options.effect, options.edge);
  while (csv.next()) {
    cause.time = core::TimePoint::from_ns(core::Clock::realtime, csv.epoch_ns(kRemoteS, kRemoteNs));
    effect.time = core::TimePoint::from_ns(core::Clock::realtime, csv.epoch_ns(kVehicleS, kVehicleNs));
    csv.expect_empty(kEmpty);
    LatencyCheck check;
    check.line = csv.line();
    check.file_latency = core::Duration{csv.decimal_ms(kLatency)};
    std::int64_t computed = 0;
    if (__builtin_sub_overflow(effect.time.ns(), cause.time.ns(), &computed))
      csv.fail("vehicle - remote_station overflows 64-bit nanoseconds");
    check.difference = core::Duration{computed} - check.file_latency;
    const auto magnitude = check.difference < core::Duration{0} ? -check.difference : check.difference;
    check.agrees = magnitude <= kRigLatencyTolerance;

    const auto index = static_cast<std::int64_t>(result.pairs.size());
    if (!check.agrees) result.disagreements.push_back(result.pairs.size());
    result.pairs.push_back(PairRow{index, index, cause.time, effect.time});
    result.causes.push_back(cause);
    result.effects.push_back(effect);
    result.checks.push_back(check);
  }
  return result;
}

void write_rig_paired_csv(std::ostream& out, const PairSource& pairs) {
  OutputBuffer buffer(out);
  buffer << join_columns(kRigPairedColumns) << '\n';
  PairBlockReader rows(pairs);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairRow& pair = rows.at(i).row;
    std::int64_t seconds = 0;
    std::int64_t nanoseconds = 0;
    split_seconds(pair.cause_time.ns(), seconds, nanoseconds);
    buffer.integer(seconds) << ',';
    buffer.integer(nanoseconds) << ',';
    split_seconds(pair.effect_time.ns(), seconds, nanoseconds);
    buffer.integer(seconds) << ',';
    buffer.integer(nanoseconds) << ",,";
    buffer << core::format_ms(pair.latency()) << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

void write_rig_paired_csv(std::ostream& out, std::span<const PairRow> pairs) {
  write_rig_paired_csv(out, PairRowsSource(pairs));
}

}  // namespace m2mlat::formats
