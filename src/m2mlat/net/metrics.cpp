// One HELP and TYPE line per family, then its samples; labels escaped.
#include "m2mlat/net/metrics.hpp"

#include <fmt/format.h>

#include <utility>

#include "m2mlat/core/time.hpp"

namespace m2mlat::net {

std::string escape_label(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

std::string render_metrics(const Status& s, const ConnectionCounts& connections) {
  std::string out;
  const auto family = [&](std::string_view name, std::string_view type, std::string_view help) {
    out += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
  };
  const auto node = fmt::format("node=\"{}\"", escape_label(s.node));
  const auto per_channel = [&](std::string_view name, std::string_view help, auto value) {
    family(name, "counter", help);
    for (const auto& c : s.channels)
      out += fmt::format("{}{{{},channel=\"{}\"}} {}\n", name, node, escape_label(c.name), value(c));
  };

  family("m2mlat_up", "gauge", "1 while the agent runs.");
  out += fmt::format("m2mlat_up{{{}}} 1\n", node);
  per_channel("m2mlat_events_total", "Events stored since the agent started.",
              [](const ChannelStatus& c) { return c.events; });
  per_channel("m2mlat_suppressed_edges_total", "Edges refused by the refractory gate (bounces).",
              [](const ChannelStatus& c) { return c.suppressed; });
  family("m2mlat_lost_events_total", "counter", "Events missing according to the kernel's sequence numbers.");
  out += fmt::format("m2mlat_lost_events_total{{{}}} {}\n", node, s.lost);
  family("m2mlat_dropped_edges_total", "counter", "Edges seen while no session was open (not stored).");
  out += fmt::format("m2mlat_dropped_edges_total{{{}}} {}\n", node, s.dropped);
  family("m2mlat_last_seq", "gauge", "The store's last committed event sequence number.");
  out += fmt::format("m2mlat_last_seq{{{}}} {}\n", node, s.last_seq);
  family("m2mlat_session_open", "gauge", "1 while a session is open.");
  out += fmt::format("m2mlat_session_open{{{}}} {}\n", node, s.session ? 1 : 0);
  family("m2mlat_http_connections_open", "gauge", "Connections to the API open now (a thread each).");
  out += fmt::format("m2mlat_http_connections_open{{{}}} {}\n", node, connections.open);
  // Accepted connections and those ended early are two families: the early endings' sum over their
  // label is meaningful on its own (Prometheus' rule for a label), and is not a part of 'accepted'.
  family("m2mlat_http_connections_accepted_total", "counter", "Connections to the API given a thread.");
  out += fmt::format("m2mlat_http_connections_accepted_total{{{}}} {}\n", node, connections.accepted);
  family("m2mlat_http_connections_ended_early_total", "counter",
         "Connections to the API ended early, by reason: evicted (to make room), refused (503, all busy), "
         "timed_out (request deadline), idle (no request began).");
  for (const auto& [reason, n] :
       {std::pair<std::string_view, std::uint64_t>{"evicted", connections.evicted},
        {"refused", connections.refused},
        {"timed_out", connections.timed_out},
        {"idle", connections.idle}})
    out += fmt::format("m2mlat_http_connections_ended_early_total{{{},reason=\"{}\"}} {}\n", node, reason, n);
  family("m2mlat_start_time_seconds", "gauge", "When the agent started, CLOCK_REALTIME seconds.");
  out += fmt::format("m2mlat_start_time_seconds{{{}}} {}\n", node, core::format_seconds(s.started_ns));
  if (s.marks) {
    family("m2mlat_marks_stored_total", "counter", "Software markers received on the marker port and stored.");
    out += fmt::format("m2mlat_marks_stored_total{{{}}} {}\n", node, s.marks->stored);
    family("m2mlat_marks_rejected_total", "counter",
           "Datagrams on the marker port refused, by reason (format, name, key, time, field, size, session, "
           "store).");
    for (const auto& [reason, n] : s.marks->rejected)
      out += fmt::format("m2mlat_marks_rejected_total{{{},reason=\"{}\"}} {}\n", node, escape_label(reason), n);
  }
  if (s.clock) {
    const auto source = fmt::format("{},source=\"{}\"", node, escape_label(s.clock->source));
    family("m2mlat_clock_offset_seconds", "gauge", "The clock's estimated offset from its reference.");
    out += fmt::format("m2mlat_clock_offset_seconds{{{}}} {}\n", source,
                       core::format_seconds(s.clock->offset_ns));
    family("m2mlat_clock_max_error_seconds", "gauge", "The clock's maximum error bound.");
    out += fmt::format("m2mlat_clock_max_error_seconds{{{}}} {}\n", source,
                       core::format_seconds(s.clock->max_error_ns));
    family("m2mlat_clock_synchronised", "gauge", "1 if the clock is synchronised to its reference.");
    out += fmt::format("m2mlat_clock_synchronised{{{}}} {}\n", source, s.clock->synchronised ? 1 : 0);
  }
  return out;
}

}  // namespace m2mlat::net
