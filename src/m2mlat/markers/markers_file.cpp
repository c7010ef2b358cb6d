#include "m2mlat/markers/markers_file.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/core/time.hpp"
#include "m2mlat/formats/fields.hpp"

namespace m2mlat::markers {

namespace {

std::string optional_ns(const std::optional<std::int64_t>& ns) { return ns ? std::to_string(*ns) : std::string(); }

nlohmann::json optional_json(const std::optional<std::int64_t>& ns) {
  return ns ? nlohmann::json(*ns) : nlohmann::json(nullptr);
}

nlohmann::json number_or_null(double value) { return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value); }

}  // namespace

std::string markers_csv(std::span<const Marker> markers) {
  // The header first, no comment line: pandas, R and DuckDB read it as it is (docs/formats.md); the
  // header is the format's identity.
  std::string out = "node,name,clock,time_ns,source,key,sender_ns,sender_to_capture_ns,origin\n";
  for (const auto& m : markers) {
    formats::append_csv_field(out, m.node);
    out += ',';
    formats::append_csv_field(out, m.name);
    out += fmt::format(",{},{},{},", core::to_string(m.time.clock()), m.time.ns(), to_string(m.source));
    formats::append_csv_field(out, m.key);
    if (m.sender_time) out += fmt::format(",{},{},", m.sender_time->ns(), m.time.ns() - m.sender_time->ns());
    else out += ",,,";
    formats::append_csv_field(out, m.origin);
    out += '\n';
  }
  return out;
}

nlohmann::json counts_json(const CaptureCounts& c) {
  return {{"seen", c.seen},               {"packets", c.packets},         {"segments", c.segments},
          {"other", c.other},             {"fragments", c.fragments},
          {"snapped", c.snapped},         {"malformed", c.malformed},
          {"messages", c.messages},       {"without_key", c.without_key},
          {"retransmitted", c.retransmitted}, {"out_of_order", c.out_of_order},
          {"incomplete_bytes", c.incomplete_bytes}, {"dropped", c.dropped}};
}

nlohmann::json markers_json(std::span<const Marker> markers, const CaptureCounts& counts) {
  auto rows = nlohmann::json::array();
  for (const auto& m : markers) {
    std::optional<std::int64_t> sender;
    std::optional<std::int64_t> to_capture;
    if (m.sender_time) {
      sender = m.sender_time->ns();
      to_capture = m.time.ns() - *sender;
    }
    rows.push_back({{"node", m.node},
                    {"name", m.name},
                    {"clock", core::to_string(m.time.clock())},
                    {"time_ns", m.time.ns()},
                    {"source", to_string(m.source)},
                    {"key", m.key},
                    {"sender_ns", optional_json(sender)},
                    {"sender_to_capture_ns", optional_json(to_capture)},
                    {"origin", m.origin}});
  }
  return {{"format", kMarkersFormat}, {"markers", std::move(rows)}, {"counts", counts_json(counts)}};
}

std::string one_way_csv(const OneWayMatch& match) {
  std::string out = "key,sent_ns,received_ns,one_way_ns,one_way_ms,sender_ns,sender_to_sent_ns,sender_to_received_ns,"
         "sent_origin,received_origin\n";
  for (const auto& c : match.commands) {
    formats::append_csv_field(out, c.key);
    out += fmt::format(",{},{},{},{},{},", c.sent_ns, c.received_ns, c.one_way_ns,
                       core::format_ms(core::Duration{c.one_way_ns}), optional_ns(c.sender_ns));
    if (c.sender_ns) out += fmt::format("{},{},", c.sent_ns - *c.sender_ns, c.received_ns - *c.sender_ns);
    else out += ",,";
    formats::append_csv_field(out, c.sent_origin);
    out += ',';
    formats::append_csv_field(out, c.received_origin);
    out += '\n';
  }
  return out;
}

nlohmann::json one_way_json(const OneWayMatch& match, const CaptureCounts& sender, const CaptureCounts& receiver) {
  auto rows = nlohmann::json::array();
  for (const auto& c : match.commands) {
    std::optional<std::int64_t> to_sent;
    std::optional<std::int64_t> to_received;
    if (c.sender_ns) {
      to_sent = c.sent_ns - *c.sender_ns;
      to_received = c.received_ns - *c.sender_ns;
    }
    rows.push_back({{"key", c.key},
                    {"sent_ns", c.sent_ns},
                    {"received_ns", c.received_ns},
                    {"one_way_ns", c.one_way_ns},
                    {"sender_ns", optional_json(c.sender_ns)},
                    {"sender_to_sent_ns", optional_json(to_sent)},
                    {"sender_to_received_ns", optional_json(to_received)},
                    {"sent_origin", c.sent_origin},
                    {"received_origin", c.received_origin}});
  }
  const auto summary = summarize(match);
  return {{"format", kOneWayFormat},
          {"commands", std::move(rows)},
          {"summary", {{"n", summary.n}, {"median_ns", number_or_null(summary.median_ns)},
                       {"p95_ns", number_or_null(summary.p95_ns)}}},
          {"unmatched", {{"sender_only", match.sender_only}, {"receiver_only", match.receiver_only},
                         {"repeated_keys", match.repeated_keys}}},
          {"sender_counts", counts_json(sender)},
          {"receiver_counts", counts_json(receiver)}};
}

}  // namespace m2mlat::markers
