// `m2mlat packets`: the commands in a capture (a pcap/pcapng file, or live on an interface) as
// markers, and with --peer the one-way time of each command matched across two captures
// (docs/markers.md).
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <optional>

#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/markers/markers_file.hpp"
#include "m2mlat/markers/one_way.hpp"
#include "m2mlat/markers/packet_markers.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::cli {

namespace {

struct PacketsCommand {
  std::string file;
  std::string interface;
  std::string duration;
  std::string filter;
  std::string key = "hash";
  std::string sender_ms;
  std::string node;
  std::string peer;
  std::string peer_node;
  std::string write;
  std::string out = "-";
  bool csv = false;
  bool json = false;
};

std::string ms_of(std::int64_t ns) { return core::format_ms(core::Duration{ns}); }

// "200 packets, 100 messages, 2 retransmitted": the counts that are not zero.
std::string counts_text(const markers::CaptureCounts& c) {
  std::string text = fmt::format("{} packets, {} messages", c.packets, c.messages);
  const std::pair<std::uint64_t, const char*> more[] = {
      {c.without_key, "without key"}, {c.other, "of other protocols"}, {c.fragments, "IP fragments"},
      {c.snapped, "cut by the snapshot length"}, {c.malformed, "malformed"}, {c.retransmitted, "TCP retransmitted"},
      {c.out_of_order, "TCP out of order"}, {c.incomplete_bytes, "TCP bytes of incomplete messages"},
      {c.dropped, "dropped by the kernel"}};
  for (const auto& [n, what] : more)
    if (n != 0) text += fmt::format(", {} {}", n, what);
  return text;
}

// A filter that passed nothing is said, with what the capture held.
void warn_if_filtered_out(const PacketsCommand& c, const markers::CaptureCounts& counts) {
  if (c.filter.empty() || counts.packets != 0) return;
  std::cerr << fmt::format("m2mlat: warning: {}: the filter '{}' passed none of its {} packets{}\n",
                           c.interface.empty() ? c.file : c.interface, c.filter, counts.seen,
                           counts.seen == 0 ? "" : "; `tcpdump -nr FILE | head` shows what they are");
}

std::vector<markers::Marker> read_capture(const PacketsCommand& c, markers::CaptureCounts& counts) {
  markers::MarkerOptions options;
  options.rule.filter = c.filter;
  options.rule.key = markers::parse_key_rule(c.key);
  options.rule.sender_ms = c.sender_ms;
  options.node = c.node;
  std::vector<markers::Marker> found;
  const auto keep = [&](markers::Marker&& m) { found.push_back(std::move(m)); };
  if (c.interface.empty()) {
    found = markers::read_file_markers(c.file, options, &counts);
    warn_if_filtered_out(c, counts);
    return found;
  }
  const auto duration = duration_flag("--duration", c.duration, true);
  capture::StopSignal stop;  // SIGINT/SIGTERM end the capture cleanly (the copy is flushed)
  auto capture = markers::Capture::open_live({.interface = c.interface});
  if (!c.filter.empty()) capture.set_filter(c.filter);
  if (!c.write.empty()) capture.write_to(c.write);
  std::cerr << fmt::format("m2mlat: capturing on {} (timestamps: {}){}\n", c.interface,
                           markers::to_string(capture.stamp_source()),
                           duration.count() > 0 ? fmt::format(" for {}", core::format_duration(duration)) : "");
  std::cerr.flush();
  const auto end = core::monotonic_now() + duration;
  counts = markers::read_markers(capture, options, keep, [&] {
    if (!stop.take().empty()) return false;
    return duration.count() == 0 || core::monotonic_now() < end;
  });
  warn_if_filtered_out(c, counts);
  return found;
}

int run_packets(const PacketsCommand& c) {
  if (c.file.empty() == c.interface.empty())
    throw core::Error(core::ErrorKind::usage, "give one capture: a FILE or --interface IF");
  if (c.csv && c.json) throw core::Error(core::ErrorKind::usage, "--csv and --json: choose one");
  if (!c.write.empty() && c.interface.empty())
    throw core::Error(core::ErrorKind::usage, "--write copies a live capture: it needs --interface");
  if (!c.duration.empty() && c.interface.empty())
    throw core::Error(core::ErrorKind::usage, "--duration is for a live capture (--interface)");
  markers::parse_key_rule(c.key);  // a bad rule fails before any capture starts
  if (c.out != "-") core::check_output_target(c.out);

  markers::CaptureCounts counts;
  const auto sent = read_capture(c, counts);
  if (c.peer.empty()) {
    if (c.json) {
      core::write_output_file(c.out, json_text(markers::markers_json(sent, counts)) + "\n");
    } else if (c.csv) {
      core::write_output_file(c.out, markers::markers_csv(sent));
    } else {
      report::Table table({"node", "capture time (s)", "key", "sender to capture (ms)", "where"});
      for (const auto& m : sent)
        table.add_row({m.node, core::format_seconds(m.time.ns()), m.key,
                       m.sender_time ? ms_of(m.time.ns() - m.sender_time->ns()) : "-", m.origin});
      core::write_output_file(c.out, fmt::format("{} markers; {}\n{}", sent.size(), counts_text(counts), table.render()));
    }
    return 0;
  }

  PacketsCommand peer = c;
  peer.file = c.peer;
  peer.interface.clear();
  peer.node = c.peer_node;
  markers::CaptureCounts peer_counts;
  const auto received = read_capture(peer, peer_counts);
  const auto match = markers::match_one_way(sent, received);
  if (c.json) {
    core::write_output_file(c.out, json_text(markers::one_way_json(match, counts, peer_counts)) + "\n");
    return 0;
  }
  if (c.csv) {
    core::write_output_file(c.out, markers::one_way_csv(match));
    return 0;
  }
  report::Table table({"key", "sent (s)", "one-way (ms)", "sender to sent (ms)", "sender to received (ms)"});
  for (const auto& command : match.commands)
    table.add_row({command.key, core::format_seconds(command.sent_ns), ms_of(command.one_way_ns),
                   command.sender_ns ? ms_of(command.sent_ns - *command.sender_ns) : "-",
                   command.sender_ns ? ms_of(command.received_ns - *command.sender_ns) : "-"});
  const auto summary = markers::summarize(match);
  std::string text = fmt::format("one-way: n {}, median {} ms, p95 {} ms\n", summary.n, report::ms_text(summary.median_ns / 1e6, 3),
                      report::ms_text(summary.p95_ns / 1e6, 3));
  text += fmt::format("unmatched: {} only in the sender's capture, {} only in the receiver's, {} repeated keys\n",
                      match.sender_only, match.receiver_only, match.repeated_keys);
  text += fmt::format("sender's capture: {}\nreceiver's capture: {}\n", counts_text(counts), counts_text(peer_counts));
  core::write_output_file(c.out, text + table.render());
  return 0;
}

}  // namespace

Runner attach_packets(CLI::App& sub) {
  auto c = std::make_shared<PacketsCommand>();
  sub.add_option("file", c->file, "A pcap or pcapng capture (tcpdump -w, Wireshark); the sender's with --peer");
  sub.add_option("-i,--interface", c->interface, "Capture live on this interface instead (needs CAP_NET_RAW)");
  sub.add_option("--duration", c->duration, "How long to capture live (e.g. 10s); default: until SIGINT/SIGTERM");
  sub.add_option("--filter", c->filter, "BPF filter naming the command packets (tcpdump syntax), e.g. 'tcp port 7000'");
  sub.add_option("--key", c->key, "How to key a command: json:NAME, bytes:OFFSET:LENGTH or hash")->capture_default_str();
  sub.add_option("--sender-ms", c->sender_ms, "JSON member holding the sender's CLOCK_REALTIME in ms, e.g. stamp");
  sub.add_option("--node", c->node, "The markers' node (default: the capture's name)");
  sub.add_option("--peer", c->peer, "The receiver's capture: match commands by key and give one-way times");
  sub.add_option("--peer-node", c->peer_node, "The receiver's node (default: the peer capture's name)");
  sub.add_option("-w,--write", c->write, "Also write the live packets the filter passes to this pcap file");
  sub.add_option("-o,--out", c->out, "Write the result here instead of standard output");
  sub.add_flag("--csv", c->csv, "CSV (m2mlat-markers/1, or m2mlat-oneway/1 with --peer)");
  sub.add_flag("--json", c->json, "JSON (the same formats)");
  return [c] { return run_packets(*c); };
}

}  // namespace m2mlat::cli
