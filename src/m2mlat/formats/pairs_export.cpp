// Writing matched pairs as CSV and JSON Lines.
#include "m2mlat/formats/pairs_export.hpp"

#include <fmt/format.h>

#include <array>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/output_text.hpp"

namespace m2mlat::formats {

namespace {

// The optional uncertainty columns, in file order, with their names; empty spans are not written.
struct OptionalColumn {
  std::string_view name;
  std::span<const std::optional<std::int64_t>> values;
};
std::array<OptionalColumn, 3> optional_columns(const PairExportOptions& options) {
  return {{{"max_error_ns", options.max_error_ns}, {"u_ns", options.u_ns}, {"U95_ns", options.U95_ns}}};
}

void check_options(std::span<const PairRow> pairs, const PairExportOptions& options) {
  auto check_size = [&](std::size_t size, std::string_view what) {
    if (size != 0 && size != pairs.size())
      throw core::Error(core::ErrorKind::internal,
                        fmt::format("pair export: {} {} for {} pairs", size, what, pairs.size()));
  };
  for (const auto& column : optional_columns(options)) check_size(column.values.size(), column.name);
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
  const auto columns = optional_columns(options);
  const bool with_flags = options.flags;
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  buffer << "# format: " << kPairsFormat << '\n';
  buffer
      << "cause_node,cause_channel,effect_node,effect_channel,clock,cause_time_ns,effect_time_ns,latency_ns,"
         "latency_ms";
  for (const auto& column : columns)
    if (!column.values.empty()) buffer << ',' << column.name;
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
    for (const auto& column : columns) {
      if (column.values.empty()) continue;
      buffer << ',';
      if (column.values[i]) buffer.integer(*column.values[i]);
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
  const auto columns = optional_columns(options);
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
    for (const auto& column : columns) {
      if (column.values.empty()) continue;
      text.append(",\"");
      text.append(column.name);
      text.append("\":");
      if (column.values[i])
        buffer.integer(*column.values[i]);
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
