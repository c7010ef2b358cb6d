// Writing matched pairs as CSV and JSON Lines.
#include "m2mlat/formats/pairs_export.hpp"

#include <fmt/format.h>

#include <array>
#include <string_view>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/output_text.hpp"
#include "m2mlat/formats/pair_rows_source.hpp"

namespace m2mlat::formats {

namespace {

// The optional uncertainty columns, in file order: each one's name, whether a source has it, and its
// value in a row.
struct OptionalColumn {
  std::string_view name;
  bool PairColumns::*present;
  std::optional<std::int64_t> PairRecord::*value;
};
constexpr std::array<OptionalColumn, 3> kOptionalColumns{
    {{"max_error_ns", &PairColumns::max_error_ns, &PairRecord::max_error_ns},
     {"u_ns", &PairColumns::u_ns, &PairRecord::u_ns},
     {"U95_ns", &PairColumns::U95_ns, &PairRecord::U95_ns}}};
// The columns `source` has, in file order.
std::vector<OptionalColumn> columns_of(const PairSource& source) {
  const PairColumns has = source.columns();
  std::vector<OptionalColumn> columns;
  for (const OptionalColumn& column : kOptionalColumns)
    if (has.*column.present) columns.push_back(column);
  return columns;
}

// The groups to write: the caller's, or one group of every pair from the options' three names.
std::vector<PairGroup> groups_of(const PairSource& pairs, const PairExportOptions& options) {
  if (!options.groups.empty()) return {options.groups.begin(), options.groups.end()};
  return {PairGroup{options.scenario, options.cause, options.effect, pairs.size()}};
}

// A group's four names with their columns, in file order: the same on every row of the group, so
// each writer formats them once per group.
struct NameField {
  std::string_view column;
  const std::string* value;
};
std::array<NameField, 4> name_fields(const PairGroup& group) {
  return {{{"cause_node", &group.cause.node},
           {"cause_channel", &group.cause.channel},
           {"effect_node", &group.effect.node},
           {"effect_channel", &group.effect.channel}}};
}

void check_options(const PairSource& pairs, const PairExportOptions& options,
                   std::span<const PairGroup> groups) {
  std::size_t total = 0;
  for (const PairGroup& group : groups) {
    total += group.count;
    // The names must read back: the same rule as for events.
    for (const core::ChannelRef* where : {&group.cause, &group.effect}) {
      core::Event probe;
      probe.node = where->node;
      probe.channel = where->channel;
      check_exportable(probe, 0);
    }
    if (group.scenario.find_first_of("\r\n") != std::string::npos)
      throw core::Error(core::ErrorKind::data, "a scenario name holds a line break");
  }
  if (total != pairs.size())
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("pair export: the groups count {} pairs, not {}", total, pairs.size()));
  for (const auto& [id, label] : options.labels)
    if (label.find_first_of("\r\n") != std::string::npos)
      throw core::Error(core::ErrorKind::data, fmt::format("session {}: its label holds a line break", id));
}

// The session id and label of a row ("" for unknown).
struct PairSession {
  std::int64_t id = 0;
  const std::string* label = nullptr;
};
PairSession session_of(const PairExportOptions& options, const PairRecord& record) {
  if (record.session == 0) return {};
  const auto found = options.labels.find(record.session);
  return {record.session, found == options.labels.end() ? nullptr : &found->second};
}

}  // namespace

void write_pairs_csv(std::ostream& out, const PairSource& pairs, const PairExportOptions& options) {
  const auto groups = groups_of(pairs, options);
  check_options(pairs, options, groups);
  const auto columns = columns_of(pairs);
  PairBlockReader rows(pairs);
  const bool with_flags = options.flags;
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  buffer << "scenario,session,label,cause_node,cause_channel,effect_node,effect_channel,clock,cause_time_ns,"
            "effect_time_ns,latency_ns,latency_ms";
  for (const auto& column : columns) buffer << ',' << column.name;
  if (with_flags) buffer << ",pair_flags";
  const bool with_statistics = pairs.columns().statistics;
  if (with_statistics) buffer << ",in_statistics,left_out";
  const bool with_probability = pairs.columns().probability;
  if (with_probability) buffer << ",probability";
  buffer << '\n';
  std::size_t i = 0;
  for (const PairGroup& group : groups) {
    // The scenario and the four names are the same on every row of the group: quote them once.
    std::string scenario;
    append_csv_field(scenario, group.scenario);
    scenario.push_back(',');
    std::string names;
    for (const NameField& field : name_fields(group)) {
      append_csv_field(names, *field.value);
      names.push_back(',');
    }
    for (const std::size_t end = i + group.count; i < end; ++i) {
      const PairRecord& record = rows.at(i);
      const PairRow& pair = record.row;
      const core::Duration latency = pair.latency();
      text.append(scenario);
      if (const PairSession session = session_of(options, record); session.id != 0) {
        buffer.integer(session.id) << ',';
        if (session.label) append_csv_field(text, *session.label);
        text.push_back(',');
      } else {
        text.append(",,");
      }
      text.append(names);
      buffer << core::to_string(pair.cause_time.clock()) << ',';
      buffer.integer(pair.cause_time.ns()) << ',';
      buffer.integer(pair.effect_time.ns()) << ',';
      buffer.integer(latency.count()) << ',';
      buffer << core::format_ms(latency);
      for (const auto& column : columns) {
        buffer << ',';
        if (const auto& value = record.*column.value) buffer.integer(*value);
      }
      if (with_flags) {
        buffer << ',';
        buffer.integer(pair.flags);
      }
      if (with_statistics) {
        buffer << (record.in_statistics ? ",true," : ",false,");
        text.append(record.left_out);
      }
      if (with_probability) {
        buffer << ',';
        if (record.probability) text.append(fmt::format("{:.9g}", *record.probability));
      }
      buffer << '\n';
      buffer.end_record();
    }
  }
  buffer.flush();
}

void write_pairs_jsonl(std::ostream& out, const PairSource& pairs, const PairExportOptions& options) {
  const auto groups = groups_of(pairs, options);
  check_options(pairs, options, groups);
  const auto columns = columns_of(pairs);
  PairBlockReader rows(pairs);
  OutputBuffer buffer(out);
  std::string& text = buffer.text();
  std::size_t i = 0;
  for (const PairGroup& group : groups) {
    std::string scenario;  // the same on every line of the group
    scenario.append("{\"format\":");
    append_json_string(scenario, kPairsFormat);
    scenario.append(",\"scenario\":");
    append_json_string(scenario, group.scenario);
    std::string names;
    for (const NameField& field : name_fields(group)) {
      names.append(",\"");
      names.append(field.column);
      names.append("\":");
      append_json_string(names, *field.value);
    }
    for (const std::size_t end = i + group.count; i < end; ++i) {
      const PairRecord& record = rows.at(i);
      const PairRow& pair = record.row;
      const core::Duration latency = pair.latency();
      text.append(scenario);
      if (const PairSession session = session_of(options, record); session.id != 0) {
        text.append(",\"session\":");
        buffer.integer(session.id);
        text.append(",\"label\":");
        if (session.label)
          append_json_string(text, *session.label);
        else
          text.append("null");
      } else {
        text.append(",\"session\":null,\"label\":null");
      }
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
        text.append(",\"");
        text.append(column.name);
        text.append("\":");
        if (const auto& value = record.*column.value)
          buffer.integer(*value);
        else
          text.append("null");
      }
      if (options.flags) {
        text.append(",\"pair_flags\":");
        buffer.integer(pair.flags);
      }
      if (pairs.columns().statistics) {
        text.append(record.in_statistics ? ",\"in_statistics\":true,\"left_out\":" : ",\"in_statistics\":false,\"left_out\":");
        if (record.left_out.empty()) {
          text.append("null");
        } else {
          text.push_back('"');
          text.append(record.left_out);
          text.push_back('"');
        }
      }
      if (pairs.columns().probability)
        text.append(record.probability ? fmt::format(",\"probability\":{:.9g}", *record.probability)
                                       : std::string(",\"probability\":null"));
      text.append("}\n");
      buffer.end_record();
    }
  }
  buffer.flush();
}

void write_pairs_csv(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options) {
  write_pairs_csv(out, PairRowsSource(pairs, options), options);
}

void write_pairs_jsonl(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options) {
  write_pairs_jsonl(out, PairRowsSource(pairs, options), options);
}

}  // namespace m2mlat::formats
