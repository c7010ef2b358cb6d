// Writing matched pairs as CSV and JSON Lines.
#include "m2mlat/formats/pairs_export.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

namespace {

void check_options(std::span<const PairRow> pairs, const PairExportOptions& options) {
  auto check_size = [&](std::size_t size, std::string_view what) {
    if (size != 0 && size != pairs.size())
      throw core::Error(core::ErrorKind::internal,
                        fmt::format("pair export: {} {} for {} pairs", size, what, pairs.size()));
  };
  check_size(options.uncertainty_ns.size(), "uncertainty values");
  check_size(options.est_error_ns.size(), "estimated errors");
  // The names must read back: the same rule as for events.
  core::Event probe;
  probe.node = options.cause.node;
  probe.channel = options.cause.channel;
  check_exportable(probe, 0);
  probe.node = options.effect.node;
  probe.channel = options.effect.channel;
  check_exportable(probe, 0);
}

}  // namespace

void write_pairs_csv(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options) {
  check_options(pairs, options);
  const bool with_uncertainty = !options.uncertainty_ns.empty();
  const bool with_flags = options.flags;
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  buffer << "# format: " << kPairsFormat << '\n';
  buffer
      << "cause_node,cause_channel,effect_node,effect_channel,clock,cause_time_ns,effect_time_ns,latency_ns,"
         "latency_ms";
  if (with_uncertainty) buffer << ",uncertainty_ns";
  if (!options.est_error_ns.empty()) buffer << ",est_error_ns";
  if (with_flags) buffer << ",flags";
  buffer << '\n';
  // The four names are the same on every row: quote them once.
  std::string names;
  append_csv_field(names, options.cause.node);
  names.push_back(',');
  append_csv_field(names, options.cause.channel);
  names.push_back(',');
  append_csv_field(names, options.effect.node);
  names.push_back(',');
  append_csv_field(names, options.effect.channel);
  names.push_back(',');
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairRow& pair = pairs[i];
    const core::Duration latency = pair.latency();
    text.append(names);
    buffer << core::to_string(pair.cause_time.clock()) << ',';
    buffer.integer(pair.cause_time.ns()) << ',';
    buffer.integer(pair.effect_time.ns()) << ',';
    buffer.integer(latency.count()) << ',';
    buffer << core::format_ms(latency);
    if (with_uncertainty) {
      buffer << ',';
      if (options.uncertainty_ns[i]) buffer.integer(*options.uncertainty_ns[i]);
    }
    if (!options.est_error_ns.empty()) {
      buffer << ',';
      if (options.est_error_ns[i]) buffer.integer(*options.est_error_ns[i]);
    }
    if (with_flags) {
      buffer << ',';
      buffer.integer(pair.flags);
    }
    buffer << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

void write_pairs_jsonl(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options) {
  check_options(pairs, options);
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  std::string names;  // the same on every line
  names.append("{\"format\":");
  append_json_string(names, kPairsFormat);
  names.append(",\"cause_node\":");
  append_json_string(names, options.cause.node);
  names.append(",\"cause_channel\":");
  append_json_string(names, options.cause.channel);
  names.append(",\"effect_node\":");
  append_json_string(names, options.effect.node);
  names.append(",\"effect_channel\":");
  append_json_string(names, options.effect.channel);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairRow& pair = pairs[i];
    const core::Duration latency = pair.latency();
    text.append(names);
    text.append(",\"clock\":\"");
    text.append(core::to_string(pair.cause_time.clock()));
    text.append("\",\"cause_time_ns\":");
    buffer.integer(pair.cause_time.ns());
    text.append(",\"effect_time_ns\":");
    buffer.integer(pair.effect_time.ns());
    text.append(",\"latency_ns\":");
    buffer.integer(latency.count());
    text.append(",\"latency_ms\":");
    text.append(core::format_ms(latency));
    if (!options.uncertainty_ns.empty()) {
      text.append(",\"uncertainty_ns\":");
      if (options.uncertainty_ns[i])
        buffer.integer(*options.uncertainty_ns[i]);
      else
        text.append("null");
    }
    if (!options.est_error_ns.empty()) {
      text.append(",\"est_error_ns\":");
      if (options.est_error_ns[i])
        buffer.integer(*options.est_error_ns[i]);
      else
        text.append("null");
    }
    if (options.flags) {
      text.append(",\"flags\":");
      buffer.integer(pair.flags);
    }
    text.append("}\n");
    buffer.end_record();
  }
  buffer.flush();
}

}  // namespace m2mlat::formats
