// ROS 2 bags in MCAP: files written byte by byte by the tests' writer (mcap_writer.hpp) read into
// markers: messages outside and inside chunks (uncompressed, zstd, lz4), log time and header.stamp in
// both CDR byte orders, keys; a bag without the topic lists those it has; a truncated or damaged file,
// an unknown compression and a topic without a header are errors naming the file and the offset.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <functional>

#include <fstream>
#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/bag_markers.hpp"
#include "m2mlat/markers/mcap_reader.hpp"
#include "m2mlat/markers/ros_header.hpp"
#include "mcap_writer.hpp"
#include "temp_dir.hpp"

namespace m2mlat::markers {
namespace {

using namespace mcap_test;

constexpr std::uint64_t kBagT0 = 1'764'000'000'000'000'000;  // ns, CLOCK_REALTIME
constexpr std::string_view kTwistStamped =
    "# A twist with reference coordinate frame and timestamp\nstd_msgs/Header header\nTwist twist\n"
    "================================================================================\nMSG: std_msgs/Header\n"
    "builtin_interfaces/Time stamp\nstring frame_id\n";
constexpr std::string_view kTwist = "Vector3  linear\nVector3  angular\n";

std::string write_bag(const testing::TempDir& dir, const std::string& name, const std::string& bytes) {
  const auto path = dir.file(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// Three channels: /cmd_vel (TwistStamped), /joy (Twist, no header), /odom (TwistStamped, never asked).
std::string definitions() {
  return schema_record(1, "geometry_msgs/msg/TwistStamped", kTwistStamped) +
         schema_record(2, "geometry_msgs/msg/Twist", kTwist) + channel_record(1, 1, "/cmd_vel") +
         channel_record(2, 2, "/joy") + channel_record(3, 1, "/odom");
}

std::string cmd(std::uint32_t seq, std::uint64_t log_offset_ns, std::int32_t sec, std::uint32_t nsec,
                bool little = true) {
  return message_record(1, seq, kBagT0 + log_offset_ns, stamped_cdr(sec, nsec, little));
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::Error& e) {
    return e.what();
  }
  return "(no error)";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Bag, MessagesOutsideAndInsideChunksOfEachCompressionBecomeMarkers) {
  testing::TempDir dir;
  for (const std::string compression : {"", "zstd", "lz4"}) {
    std::string data = definitions() + cmd(1, 1'000, 1'764'000'000, 500);
    data += chunk_record(cmd(2, 2'000, 1'764'000'000, 1'500, false) + message_record(2, 1, kBagT0 + 2'500, "\0\1\0\0") +
                             cmd(3, 3'000, 1'764'000'000, 2'500),
                         compression);
    const auto path = write_bag(dir, "run" + compression + ".mcap", mcap_file(data, channel_record(1, 1, "/cmd_vel")));
    BagOptions options;
    options.topics = {parse_bag_topic("/cmd_vel:cmd_sent")};
    const auto got = bag_markers(path, options);
    ASSERT_EQ(got.markers.size(), 3u) << compression;
    for (std::size_t i = 0; i < 3; ++i) {
      const auto& m = got.markers[i];
      EXPECT_EQ(m.name, "cmd_sent");
      EXPECT_EQ(m.node, "run" + compression);
      EXPECT_EQ(m.source, StampSource::bag_log);
      EXPECT_EQ(m.time.ns(), static_cast<std::int64_t>(kBagT0 + 1'000 * (i + 1)));
      ASSERT_TRUE(m.sender_time);
      EXPECT_EQ(m.sender_time->ns(), 1'764'000'000'000'000'000 + 500 + 1'000 * static_cast<std::int64_t>(i));
      EXPECT_TRUE(m.key.empty());
    }
    EXPECT_TRUE(has(got.markers[0].origin, "offset ")) << got.markers[0].origin;
    EXPECT_TRUE(has(got.markers[1].origin, "chunk at offset ")) << got.markers[1].origin;
    ASSERT_EQ(got.topics.size(), 3u);
    EXPECT_EQ(got.topics[0].messages, 3u);
    EXPECT_EQ(got.topics[1].messages, 1u);
    EXPECT_EQ(got.topics[0].type, "geometry_msgs/msg/TwistStamped");
  }
}

TEST(Bag, HeaderTimeAndKeys) {
  testing::TempDir dir;
  const auto path =
      write_bag(dir, "b.mcap", mcap_file(definitions() + cmd(7, 10, 1'764'000'001, 999'999'999) + cmd(8, 20, 5, 0)));
  BagOptions options;
  options.topics = {parse_bag_topic("/cmd_vel")};
  options.time = BagTime::header;
  options.key = BagKey::stamp;
  options.node = "station";
  const auto got = bag_markers(path, options);
  ASSERT_EQ(got.markers.size(), 2u);
  EXPECT_EQ(got.markers[0].name, "/cmd_vel");
  EXPECT_EQ(got.markers[0].node, "station");
  EXPECT_EQ(got.markers[0].source, StampSource::bag_header);
  EXPECT_EQ(got.markers[0].time.ns(), 1'764'000'001'999'999'999);
  EXPECT_EQ(got.markers[0].key, "1764000001999999999");
  EXPECT_FALSE(got.markers[0].sender_time);
  EXPECT_EQ(got.markers[1].time.ns(), 5'000'000'000);
  options.time = BagTime::log;
  options.key = BagKey::sequence;
  EXPECT_EQ(bag_markers(path, options).markers[1].key, "8");
}

TEST(Bag, ATopicWithoutHeaderGivesLogTimesOnlyAndRefusesHeaderTime) {
  testing::TempDir dir;
  const auto path = write_bag(dir, "j.mcap", mcap_file(definitions() + message_record(2, 1, kBagT0, "\0\1\0\0")));
  BagOptions options;
  options.topics = {parse_bag_topic("/joy")};
  const auto got = bag_markers(path, options);
  ASSERT_EQ(got.markers.size(), 1u);
  EXPECT_FALSE(got.markers[0].sender_time);
  options.time = BagTime::header;
  const auto message = error_of([&] { bag_markers(path, options); });
  EXPECT_TRUE(has(message, "/joy")) << message;
  EXPECT_TRUE(has(message, "no std_msgs/Header")) << message;
}

TEST(Bag, ABagWithoutTheTopicListsItsTopics) {
  testing::TempDir dir;
  const auto path = write_bag(dir, "n.mcap", mcap_file(definitions() + cmd(1, 1, 1, 1)));
  BagOptions options;
  options.topics = {parse_bag_topic("/steering")};
  const auto message = error_of([&] { bag_markers(path, options); });
  EXPECT_TRUE(has(message, path)) << message;
  EXPECT_TRUE(has(message, "no topic /steering")) << message;
  EXPECT_TRUE(has(message, "/cmd_vel (geometry_msgs/msg/TwistStamped, 1 messages)")) << message;
  EXPECT_TRUE(has(message, "/odom")) << message;
}

TEST(Bag, TruncatedAndDamagedFilesNameTheFileAndTheOffset) {
  testing::TempDir dir;
  const std::string whole = mcap_file(definitions() + cmd(1, 1, 1, 1) + cmd(2, 2, 2, 2));
  BagOptions options;
  options.topics = {parse_bag_topic("/cmd_vel")};
  // Cut inside the second message: its record runs past the end.
  const std::size_t cut = std::string(kWriterMagic).size() + header_record().size() + definitions().size() +
                          cmd(1, 1, 1, 1).size() + 20;
  const auto truncated = write_bag(dir, "t.mcap", whole.substr(0, cut));
  auto message = error_of([&] { bag_markers(truncated, options); });
  EXPECT_TRUE(has(message, truncated)) << message;
  EXPECT_TRUE(has(message, fmt::format("offset {}: truncated", cut - 20))) << message;
  // Cut between records: no footer.
  const auto no_footer = write_bag(dir, "f.mcap", whole.substr(0, cut - 20));
  message = error_of([&] { bag_markers(no_footer, options); });
  EXPECT_TRUE(has(message, "no Footer")) << message;
  const auto not_mcap = write_bag(dir, "x.mcap", "#ROSBAG V2.0\n");
  message = error_of([&] { bag_markers(not_mcap, options); });
  EXPECT_TRUE(has(message, "not an MCAP file")) << message;
  // A message naming a channel never defined.
  const auto stray = write_bag(dir, "s.mcap", mcap_file(message_record(9, 1, 1, "")));
  message = error_of([&] { bag_markers(stray, options); });
  EXPECT_TRUE(has(message, "channel 9")) << message;
  EXPECT_TRUE(has(message, fmt::format("offset {}", kWriterMagic.size() + header_record().size()))) << message;
  try {
    bag_markers(dir.file("missing.mcap"), options);
    ADD_FAILURE() << "read a missing file";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    EXPECT_TRUE(has(e.what(), "missing.mcap")) << e.what();
  }
}

TEST(Bag, ChunkProblemsAreErrors) {
  testing::TempDir dir;
  BagOptions options;
  options.topics = {parse_bag_topic("/cmd_vel")};
  const auto bz2 = write_bag(dir, "c.mcap", mcap_file(definitions() + chunk_record(cmd(1, 1, 1, 1), "bz2")));
  auto message = error_of([&] { bag_markers(bz2, options); });
  EXPECT_TRUE(has(message, "compression 'bz2' is not supported")) << message;
  EXPECT_TRUE(has(message, bz2 + ": offset ")) << message;
  const auto bad_crc = write_bag(dir, "r.mcap", mcap_file(definitions() + chunk_record(cmd(1, 1, 1, 1), "zstd", 12345)));
  message = error_of([&] { bag_markers(bad_crc, options); });
  EXPECT_TRUE(has(message, "CRC-32")) << message;
  // A chunk whose records say a length beyond the chunk.
  std::string inner = cmd(1, 1, 1, 1);
  inner[1] = static_cast<char>(0x7F);
  const auto overlong = write_bag(dir, "o.mcap", mcap_file(definitions() + chunk_record(inner, "")));
  message = error_of([&] { bag_markers(overlong, options); });
  EXPECT_TRUE(has(message, "chunk at offset")) << message;
  EXPECT_TRUE(has(message, "runs past the chunk's end")) << message;
}

TEST(Bag, HeaderDetectionAndStampDecoding) {
  EXPECT_TRUE(schema_has_header("ros2msg", kTwistStamped));
  EXPECT_TRUE(schema_has_header("ros2msg", "  Header header # comment\nfloat64 x"));
  EXPECT_FALSE(schema_has_header("ros2msg", kTwist));
  EXPECT_FALSE(schema_has_header("ros2idl", kTwistStamped));
  EXPECT_FALSE(schema_has_header("ros2msg", "int32 A=1\nstd_msgs/Header header"));
  EXPECT_EQ(header_stamp_ns(stamped_cdr(-1, 5), "m"), -1'000'000'000 + 5);
  EXPECT_EQ(header_stamp_ns(stamped_cdr(3, 7, false), "m"), 3'000'000'007);
  EXPECT_THROW(header_stamp_ns(std::string(8, '\0'), "m"), core::Error);
  std::string pl = stamped_cdr(3, 7);
  pl[1] = 0x03;  // PL_CDR_LE
  EXPECT_THROW(header_stamp_ns(pl, "m"), core::Error);
  EXPECT_THROW(header_stamp_ns(stamped_cdr(3, 1'000'000'000), "m"), core::Error);
  EXPECT_THROW(parse_bag_topic("/x:"), core::Error);
  EXPECT_THROW(parse_bag_time("both"), core::Error);
}

}  // namespace
}  // namespace m2mlat::markers
