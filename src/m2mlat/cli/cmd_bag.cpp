// `m2mlat bag BAG --topic /name[:MARKER]`: the messages of named topics of a ROS 2 bag (MCAP) as
// markers (docs/markers.md, "Markers from ROS 2 bags"): written as m2mlat-markers/1, and with --store
// kept in a board's store as a session of their own (so merge, collect and export carry them).
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/markers/bag_markers.hpp"
#include "m2mlat/markers/markers_file.hpp"
#include "m2mlat/markers/stored_markers.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct BagCommand {
  std::string bag;
  std::vector<std::string> topics;
  std::string time = "log";
  std::string key = "none";
  std::string node;
  std::string out = "-";
  std::string store_path;
  std::string scenario;
  bool quiet = false;
};

// The markers as one ended session of the store: from the first marker's time to the last.
void store_bag_markers(const BagCommand& c, const markers::BagMarkers& found, const std::string& node) {
  auto store = store::Store::open(c.store_path);
  store::Session session;
  session.label = fmt::format("bag {}", c.bag);
  session.scenario = c.scenario;
  session.node = node;
  session.role = core::Role::observer;
  session.config_json = nlohmann::json{{"bag", c.bag}, {"topics", c.topics}, {"time", c.time}, {"key", c.key}}.dump();
  const auto& all = found.markers;
  const auto [first, last] = std::minmax_element(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.time < b.time;
  });
  session.start = all.empty() ? core::realtime_now() : first->time;
  const auto id = store.begin_session(session);
  std::vector<store::MarkerRecord> rows;
  rows.reserve(all.size());
  for (const auto& m : all) rows.push_back(markers::to_record(m, id));
  store.append_markers(rows);
  store.end_session(id, all.empty() ? session.start : last->time);
}

int run_bag(const BagCommand& c) {
  markers::BagOptions options;
  for (const auto& t : c.topics) options.topics.push_back(markers::parse_bag_topic(t));
  options.time = markers::parse_bag_time(c.time);
  options.key = markers::parse_bag_key(c.key);
  options.node = c.node;
  if (!c.scenario.empty() && c.store_path.empty())
    throw core::Error(core::ErrorKind::usage, "--scenario needs --store");
  const auto found = markers::bag_markers(c.bag, options);
  if (!c.store_path.empty()) {
    store_bag_markers(c, found, found.markers.empty() ? (c.node.empty() ? c.bag : c.node) : found.markers.front().node);
  }
  if (c.store_path.empty() || c.out != "-") core::write_output_file(c.out, markers::markers_csv(found.markers));
  if (!c.quiet) {
    for (const auto& t : found.topics)
      fmt::print(stderr, "m2mlat: {}: {} ({}): {} messages\n", core::printable(c.bag), core::printable(t.topic),
                 core::printable(t.type.empty() ? "no schema" : t.type), t.messages);
    fmt::print(stderr, "m2mlat: {} markers{}\n", found.markers.size(),
               c.store_path.empty() ? "" : fmt::format(" stored in {}", core::printable(c.store_path)));
  }
  return 0;
}

}  // namespace

Runner attach_bag(CLI::App& sub) {
  auto c = std::make_shared<BagCommand>();
  sub.add_option("bag", c->bag, "The ROS 2 bag: an .mcap file, or a rosbag2 folder (metadata.yaml and its .mcap files)")->required();
  sub.add_option("--topic", c->topics, "TOPIC or TOPIC:MARKERNAME (repeatable); the marker's name is the topic by default")
      ->required();
  sub.add_option("--time", c->time,
                 "log: the message's log time, header.stamp as the sender's time; header: header.stamp itself")
      ->capture_default_str();
  sub.add_option("--key", c->key, "none, stamp (header.stamp in ns), or sequence (the recorder's)")
      ->capture_default_str();
  sub.add_option("--node", c->node, "The markers' node (default: the bag's file name)");
  sub.add_option("-o,--out", c->out, "m2mlat-markers/1 CSV ('-' = standard output; with --store only if given)")
      ->capture_default_str();
  sub.add_option("--store", c->store_path, "Also keep the markers in this store, as a session of their own");
  sub.add_option("--scenario", c->scenario, "--store: the session's scenario");
  sub.add_flag("-q,--quiet", c->quiet, "No summary on stderr");
  return [c] { return run_bag(*c); };
}

}  // namespace m2mlat::cli
