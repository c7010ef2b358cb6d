#include "m2mlat/markers/bag_markers.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/markers/mcap_reader.hpp"
#include "m2mlat/markers/ros_header.hpp"

namespace m2mlat::markers {

BagTopic parse_bag_topic(const std::string& text) {
  BagTopic out;
  const auto colon = text.rfind(':');
  out.topic = colon == std::string::npos ? text : text.substr(0, colon);
  if (colon != std::string::npos) out.marker = text.substr(colon + 1);
  if (out.topic.empty() || (colon != std::string::npos && out.marker.empty()))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("--topic '{}': use TOPIC or TOPIC:MARKERNAME, e.g. /cmd_vel:cmd_sent",
                                  core::printable(text)));
  return out;
}

BagTime parse_bag_time(const std::string& text) {
  if (text == "log") return BagTime::log;
  if (text == "header") return BagTime::header;
  throw core::Error(core::ErrorKind::usage, fmt::format("--time '{}': log or header", core::printable(text)));
}

BagKey parse_bag_key(const std::string& text) {
  if (text == "none") return BagKey::none;
  if (text == "stamp") return BagKey::stamp;
  if (text == "sequence") return BagKey::sequence;
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("--key '{}': none, stamp or sequence", core::printable(text)));
}


namespace {

// rosbag2's sqlite3 storage: not MCAP.
[[noreturn]] void refuse_db3(const std::string& path) {
  throw core::Error(core::ErrorKind::data,
                    fmt::format("{}: a rosbag2 bag in sqlite3 storage (.db3); m2mlat reads MCAP: convert it with "
                                "`ros2 bag convert -i BAG -o out.yaml` (out.yaml: output_bags: [{{uri: BAG_mcap, "
                                "storage_id: mcap}}])",
                                path));
}

// The MCAP files of a bag: the file itself, or a rosbag2 folder's .mcap files in the order of
// their split number (<bag>_0.mcap, <bag>_1.mcap, ... <bag>_10.mcap).
std::vector<std::string> bag_files(const std::string& path) {
  namespace fs = std::filesystem;
  if (fs::path(path).extension() == ".db3") refuse_db3(path);
  if (!fs::is_directory(path)) return {path};
  std::vector<std::pair<std::pair<std::size_t, std::string>, std::string>> found;  // (split, name) -> path
  bool db3 = false;
  for (const auto& entry : fs::directory_iterator(path)) {
    const auto file = entry.path();
    if (file.extension() == ".db3") db3 = true;
    if (file.extension() != ".mcap") continue;
    const std::string stem = file.stem().string();
    const auto underscore = stem.find_last_of('_');
    std::size_t split = 0;
    if (underscore != std::string::npos && stem.find_first_not_of("0123456789", underscore + 1) == std::string::npos &&
        underscore + 1 < stem.size())
      split = std::stoul(stem.substr(underscore + 1));
    found.push_back({{split, file.filename().string()}, file.string()});
  }
  if (found.empty() && db3) refuse_db3(path);
  if (found.empty())
    throw core::Error(core::ErrorKind::no_input, fmt::format("{}: a folder without .mcap files (a rosbag2 bag holds "
                                                             "metadata.yaml and <bag>_0.mcap ...)", path));
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

// The markers' node by default: a file's name without its extension, a folder's name.
std::string default_node(const std::string& path) {
  auto p = std::filesystem::path(path).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "bag/"
  return std::filesystem::is_directory(path) ? p.filename().string() : p.stem().string();
}

// One MCAP file's markers and topic counts (bag_markers without the check of missing topics).
void file_markers(const std::string& path, const BagOptions& options, const std::string& node, BagMarkers& out) {
  std::map<std::string, std::string> wanted;  // topic -> marker name
  for (const auto& t : options.topics) wanted[t.topic] = t.marker.empty() ? t.topic : t.marker;
  const bool need_stamp_always = options.time == BagTime::header || options.key == BagKey::stamp;

  // Whether each chosen channel's type has a header, decided at its first message.
  std::map<std::uint16_t, bool> header_of;
  const std::string& where_file = path;
  const McapSummary result = read_mcap(path, [&](const McapChannel& channel, const McapSchema* schema,
                                                 const McapMessage& message) {
    const auto w = wanted.find(channel.topic);
    if (w == wanted.end()) return;
    bool has_header = false;
    if (const auto h = header_of.find(channel.id); h != header_of.end()) {
      has_header = h->second;
    } else {
      has_header = channel.message_encoding == "cdr" && schema != nullptr &&
                   schema_has_header(schema->encoding, schema->data);
      header_of[channel.id] = has_header;
    }
    const std::string where = fmt::format("{}: {} (topic {})", where_file, message.where, channel.topic);
    if (need_stamp_always && !has_header)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: topic {} ({}, {}) has no std_msgs/Header first: use --time log and "
                                    "--key none or sequence",
                                    where_file, channel.topic, schema == nullptr ? "no schema" : schema->name,
                                    channel.message_encoding));
    if (message.log_time > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      throw core::Error(core::ErrorKind::data, fmt::format("{}: log_time {} is beyond int64 ns", where, message.log_time));
    std::optional<std::int64_t> stamp;
    if (has_header) stamp = header_stamp_ns(message.data, where);
    Marker m;
    m.node = node;
    m.name = w->second;
    if (options.time == BagTime::header) {
      m.time = core::TimePoint::from_ns(core::Clock::realtime, *stamp);
      m.source = StampSource::bag_header;
    } else {
      m.time = core::TimePoint::from_ns(core::Clock::realtime, static_cast<std::int64_t>(message.log_time));
      m.source = StampSource::bag_log;
      if (stamp) m.sender_time = core::TimePoint::from_ns(core::Clock::realtime, *stamp);
    }
    if (options.key == BagKey::stamp) m.key = std::to_string(*stamp);
    else if (options.key == BagKey::sequence) m.key = std::to_string(message.sequence);
    m.origin = fmt::format("{}@{} {}", std::filesystem::path(path).filename().string(), message.where, channel.topic);
    out.markers.push_back(std::move(m));
  });
  for (const auto& [id, channel] : result.channels) {
    BagTopicCount count;
    count.topic = channel.topic;
    if (const auto s = result.schemas.find(channel.schema_id); s != result.schemas.end()) count.type = s->second.name;
    if (const auto n = result.messages.find(id); n != result.messages.end()) count.messages = n->second;
    // A topic again in a later file of the bag adds its messages to the first file's count.
    const auto same = std::find_if(out.topics.begin(), out.topics.end(), [&](const auto& t) { return t.topic == count.topic; });
    if (same != out.topics.end()) same->messages += count.messages;
    else out.topics.push_back(std::move(count));
  }
}

}  // namespace

BagMarkers bag_markers(const std::string& path, const BagOptions& options) {
  if (options.topics.empty()) throw core::Error(core::ErrorKind::usage, "no --topic given");
  const std::string node = options.node.empty() ? default_node(path) : options.node;
  BagMarkers out;
  for (const auto& file : bag_files(path)) file_markers(file, options, node, out);
  std::set<std::string> present;
  for (const auto& t : out.topics) present.insert(t.topic);
  for (const auto& t : options.topics) {
    if (present.contains(t.topic)) continue;
    std::vector<std::string> listed;
    for (const auto& have : out.topics)
      listed.push_back(fmt::format("{} ({}, {} messages)", have.topic, have.type.empty() ? "no schema" : have.type,
                                   have.messages));
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: the bag has no topic {}; its topics: {}", path, core::printable(t.topic),
                                  listed.empty() ? std::string("none") : fmt::format("{}", fmt::join(listed, ", "))));
  }
  return out;
}

}  // namespace m2mlat::markers
