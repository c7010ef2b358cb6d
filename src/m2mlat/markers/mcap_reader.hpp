// A reader of MCAP files, the container of ROS 2 bags (`ros2 bag record`, rosbag2's default storage
// since Iron), written from the format's specification (https://mcap.dev/spec): the magic
// "\x89MCAP0\r\n" at both ends; records of opcode (uint8), length (uint64 LE) and content; Header,
// Schema, Channel and Message records, Chunks of them (uncompressed, zstd or lz4 frame; the
// uncompressed CRC-32 checked when written), Data End, the summary section (skipped: it repeats what
// the data section holds) and the Footer. Other records (indexes, attachments, metadata, statistics)
// are skipped by their length.
//
// The file is mapped, not read: a bag of gigabytes costs no copy, only the chunks are decompressed,
// one at a time. A file that is not MCAP, is cut short (no Footer and closing magic: a recording
// that was killed) or has a record that breaks the format is a core::Error(data) naming the file
// and the byte offset.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

namespace m2mlat::markers {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      // e.g. "geometry_msgs/msg/TwistStamped"
  std::string encoding;  // e.g. "ros2msg"
  std::string data;      // the message definition (for ros2msg: the .msg text and its dependencies)
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // "cdr" for ROS 2
};

struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      // ns since the epoch: when the recorder received the message
  std::uint64_t publish_time = 0;  // ns since the epoch: when it was published (0 when unknown)
  std::string_view data;           // the serialized message (CDR for ROS 2); valid during the call
  std::string where;               // "offset N" or "chunk at offset N, byte M": for messages
};

// What a read found besides the messages.
struct McapSummary {
  std::string profile;  // the Header's profile, "ros2" for ROS 2 bags
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::map<std::uint16_t, std::uint64_t> messages;  // per channel id
  std::uint64_t chunks = 0;
};

// `schema` is the channel's (nullptr for a channel without one).
using McapOnMessage =
    std::function<void(const McapChannel& channel, const McapSchema* schema, const McapMessage& message)>;

// Reads the whole file, calling on_message for each message in file order (chunks in order, each
// chunk's messages in its order). Throws core::Error: no_input if the file cannot be opened, data
// as above (also for a compression other than none, zstd and lz4).
McapSummary read_mcap(const std::string& path, const McapOnMessage& on_message);

}  // namespace m2mlat::markers
