// Markers read from a ROS 2 bag (MCAP): each message of the named topics gives one marker, at its log
// time (when `ros2 bag record` received it: source bag_log) with the message's header.stamp as the
// sender's time when its type has a std_msgs/Header, or at the header.stamp itself (source
// bag_header). Both are CLOCK_REALTIME ns of the machine that took them (ROS 2's system time), so a
// bag recorded on a synchronised board gives markers on the campaign's time base (docs/markers.md,
// "Markers from ROS 2 bags").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

struct BagTopic {
  std::string topic;   // "/cmd_vel"
  std::string marker;  // the markers' name; empty: the topic
};

// "TOPIC" or "TOPIC:NAME" (the name after the last ':'). Throws core::Error(usage) for an empty part.
BagTopic parse_bag_topic(const std::string& text);

enum class BagTime : std::uint8_t {
  log,     // the marker's time is the log time; header.stamp, when there is one, is the sender's time
  header,  // the marker's time is header.stamp (a topic without a header is an error)
};
BagTime parse_bag_time(const std::string& text);  // "log" | "header"; throws core::Error(usage)

enum class BagKey : std::uint8_t {
  none,    // no key
  stamp,   // header.stamp in ns, as text: ROS nodes copy the stamp of the message they act on, so it
           // identifies a command along the pipeline (a topic without a header is an error)
  sequence,  // the recorder's sequence number of the message on its channel (0 when not written)
};
BagKey parse_bag_key(const std::string& text);  // "none" | "stamp" | "sequence"

struct BagOptions {
  std::vector<BagTopic> topics;  // at least one
  BagTime time = BagTime::log;
  BagKey key = BagKey::none;
  std::string node;  // the markers' node; empty: the file's name without its folder and extension
};

struct BagTopicCount {
  std::string topic;
  std::string type;  // the schema's name ("" without a schema)
  std::uint64_t messages = 0;
};

struct BagMarkers {
  std::vector<Marker> markers;        // in file order
  std::vector<BagTopicCount> topics;  // every topic of the bag, in channel order
};

// Throws core::Error: data for a damaged bag (file and offset), a topic of options.topics the bag
// does not have (listing those it has), a header needed but missing; no_input for a missing file.
BagMarkers bag_markers(const std::string& path, const BagOptions& options);

}  // namespace m2mlat::markers
