// TCP streams of length-prefixed JSON commands on a raw-IP capture (the teleoperation stack's
// traffic): segments that split and join messages, arrive out of order or are retransmitted give
// each command once, stamped with the packet that completed it.
#include <gtest/gtest.h>
#include <pcap/pcap.h>

#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/capture_writer.hpp"
#include "m2mlat/markers/packet_markers.hpp"
#include "temp_dir.hpp"

namespace m2mlat::markers {
namespace {

constexpr std::int64_t kStreamT0 = 1'764'000'000'000'000'000;

std::string stream_command(int seq, std::int64_t stamp_ms) {
  return "{\"cmd\":{\"steer\":0.1,\"stamp\":1},\"seq\":" + std::to_string(seq) + ",\"stamp\":" + std::to_string(stamp_ms) + "}";
}

MarkerOptions rule() {
  MarkerOptions options;
  options.rule.filter = "tcp port 7000";
  options.rule.key = parse_key_rule("json:stamp");
  options.rule.sender_ms = "stamp";
  return options;
}

// The stream's bytes: commands 0..n-1, each length-prefixed, stamps 1764000000000 + 10 i ms.
std::vector<std::uint8_t> stream_bytes(int n) {
  std::vector<std::uint8_t> out;
  for (int i = 0; i < n; ++i) {
    const auto m = length_prefixed(stream_command(i, 1'764'000'000'000 + 10 * i));
    out.insert(out.end(), m.begin(), m.end());
  }
  return out;
}

struct Piece {
  std::size_t from;  // stream offset
  std::size_t to;
};

// Writes a capture: a SYN with sequence isn, then the stream's pieces in the given order, packet k
// at time kStreamT0 + k ms.
std::string write_stream(const testing::TempDir& dir, const std::vector<std::uint8_t>& stream,
                         const std::vector<Piece>& pieces, std::uint32_t isn = 1000) {
  const auto path = dir.file("tcp.pcap");
  CaptureWriter writer(path, DLT_RAW);
  const auto flow = make_flow(Transport::tcp, "192.168.1.10", 50000, "192.168.1.20", 7000);
  const auto back = make_flow(Transport::tcp, "192.168.1.20", 7000, "192.168.1.10", 50000);
  writer.write(kStreamT0, build_frame(DLT_RAW, flow, {}, isn, kTcpSyn));
  writer.write(kStreamT0, build_frame(DLT_RAW, back, {}, 77, kTcpSyn | kTcpAck));
  std::int64_t k = 1;
  for (const auto& piece : pieces) {
    const auto data = std::span<const std::uint8_t>(stream).subspan(piece.from, piece.to - piece.from);
    writer.write(kStreamT0 + k * 1'000'000, build_frame(DLT_RAW, flow, data, isn + 1 + static_cast<std::uint32_t>(piece.from)));
    writer.write(kStreamT0 + k * 1'000'000 + 1, build_frame(DLT_RAW, back, {}, 78));  // the ACK: no data
    ++k;
  }
  return path;
}

std::vector<std::size_t> message_ends(int n) {
  std::vector<std::size_t> ends;
  std::size_t at = 0;
  for (int i = 0; i < n; ++i) {
    at += 4 + stream_command(i, 1'764'000'000'000 + 10 * i).size();
    ends.push_back(at);
  }
  return ends;
}

TEST(TcpStreams, OneSegmentPerMessage) {
  testing::TempDir dir;
  const auto stream = stream_bytes(3);
  const auto ends = message_ends(3);
  const auto path = write_stream(dir, stream, {{0, ends[0]}, {ends[0], ends[1]}, {ends[1], ends[2]}});
  CaptureCounts counts;
  const auto markers = read_file_markers(path, rule(), &counts);
  ASSERT_EQ(markers.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(markers[i].key, std::to_string(1'764'000'000'000 + 10 * i));
    EXPECT_EQ(markers[i].time.ns(), kStreamT0 + (i + 1) * 1'000'000);
    EXPECT_EQ(markers[i].sender_time->ns(), (1'764'000'000'000 + 10 * i) * 1'000'000);
  }
  EXPECT_EQ(counts.messages, 3u);
  EXPECT_EQ(counts.incomplete_bytes, 0u);
}

TEST(TcpStreams, SplitAndJoinedMessagesAreStampedByTheCompletingPacket) {
  testing::TempDir dir;
  const auto stream = stream_bytes(4);
  const auto ends = message_ends(4);
  // Packet 1: the first 2 bytes of the length prefix; packet 2: the rest of message 0, all of 1 and
  // half of 2; packet 3: the rest of 2 and all of 3.
  const std::size_t half = ends[1] + (ends[2] - ends[1]) / 2;
  const auto path = write_stream(dir, stream, {{0, 2}, {2, half}, {half, ends[3]}});
  const auto markers = read_file_markers(path, rule());
  ASSERT_EQ(markers.size(), 4u);
  EXPECT_EQ(markers[0].time.ns(), kStreamT0 + 2'000'000);
  EXPECT_EQ(markers[1].time.ns(), kStreamT0 + 2'000'000);
  EXPECT_EQ(markers[2].time.ns(), kStreamT0 + 3'000'000);
  EXPECT_EQ(markers[3].time.ns(), kStreamT0 + 3'000'000);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(markers[i].key, std::to_string(1'764'000'000'000 + 10 * i));
}

TEST(TcpStreams, OutOfOrderSegmentsWaitForTheGap) {
  testing::TempDir dir;
  const auto stream = stream_bytes(3);
  const auto ends = message_ends(3);
  // Message 1 and 2 arrive before message 0; message 0's packet (the 3rd) completes all three.
  const auto path = write_stream(dir, stream, {{ends[0], ends[1]}, {ends[1], ends[2]}, {0, ends[0]}});
  CaptureCounts counts;
  const auto markers = read_file_markers(path, rule(), &counts);
  ASSERT_EQ(markers.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(markers[i].key, std::to_string(1'764'000'000'000 + 10 * i));  // in stream order
    EXPECT_EQ(markers[i].time.ns(), kStreamT0 + 3'000'000);
  }
  EXPECT_EQ(counts.out_of_order, 2u);
}

TEST(TcpStreams, RetransmissionsAndOverlapsGiveEachMessageOnce) {
  testing::TempDir dir;
  const auto stream = stream_bytes(3);
  const auto ends = message_ends(3);
  // Message 0; message 0 again (a retransmission); half of 1; 1 and 2 again from the start of 1
  // (overlapping the half already seen); all of it once more.
  const std::size_t half = ends[0] + 5;
  const auto path =
      write_stream(dir, stream, {{0, ends[0]}, {0, ends[0]}, {ends[0], half}, {ends[0], ends[2]}, {0, ends[2]}});
  CaptureCounts counts;
  const auto markers = read_file_markers(path, rule(), &counts);
  ASSERT_EQ(markers.size(), 3u);
  EXPECT_EQ(markers[0].time.ns(), kStreamT0 + 1'000'000);
  EXPECT_EQ(markers[1].time.ns(), kStreamT0 + 4'000'000);
  EXPECT_EQ(markers[2].time.ns(), kStreamT0 + 4'000'000);
  EXPECT_EQ(counts.retransmitted, 2u);
}

TEST(TcpStreams, SequenceNumbersWrapAround) {
  testing::TempDir dir;
  const auto stream = stream_bytes(3);
  const auto ends = message_ends(3);
  const auto path = write_stream(dir, stream, {{0, ends[0]}, {ends[0], ends[1]}, {ends[1], ends[2]}}, 0xFFFFFFF0u);
  const auto markers = read_file_markers(path, rule());
  ASSERT_EQ(markers.size(), 3u);
  EXPECT_EQ(markers[2].key, std::to_string(1'764'000'000'020));
}

TEST(TcpStreams, CaptureStartingMidStreamStartsAtTheFirstSegment) {
  testing::TempDir dir;
  const auto path = dir.file("mid.pcap");
  {
    CaptureWriter writer(path, DLT_RAW);
    const auto flow = make_flow(Transport::tcp, "192.168.1.10", 50000, "192.168.1.20", 7000);
    const auto m = length_prefixed(stream_command(0, 5));
    writer.write(kStreamT0, build_frame(DLT_RAW, flow, m, 123456));
  }
  const auto markers = read_file_markers(path, rule());
  ASSERT_EQ(markers.size(), 1u);
  EXPECT_EQ(markers[0].key, "5");
}

TEST(TcpStreams, AStreamThatIsNotLengthPrefixedIsAnErrorNamingThePacket) {
  testing::TempDir dir;
  const auto path = dir.file("http.pcap");
  {
    CaptureWriter writer(path, DLT_RAW);
    const auto flow = make_flow(Transport::tcp, "192.168.1.10", 50000, "192.168.1.20", 7000);
    writer.write(kStreamT0, build_frame(DLT_RAW, flow, bytes_of("GET / HTTP/1.1\r\n\r\n"), 1));
  }
  try {
    read_file_markers(path, rule());
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    const std::string what = e.what();
    EXPECT_NE(what.find(path + ": packet 1: tcp 192.168.1.10:50000>192.168.1.20:7000"), std::string::npos) << what;
  }
}

TEST(TcpStreams, AMessageLeftIncompleteIsCounted) {
  testing::TempDir dir;
  const auto stream = stream_bytes(2);
  const auto ends = message_ends(2);
  const auto path = write_stream(dir, stream, {{0, ends[0]}, {ends[0], ends[1] - 3}});
  CaptureCounts counts;
  const auto markers = read_file_markers(path, rule(), &counts);
  EXPECT_EQ(markers.size(), 1u);
  EXPECT_EQ(counts.incomplete_bytes, ends[1] - 3 - ends[0]);
}

TEST(TcpStreams, ASegmentTheCaptureMissedHoldsBackWhatFollows) {
  testing::TempDir dir;
  const auto stream = stream_bytes(4);
  const auto ends = message_ends(4);
  // Message 1's segment never captured: 0 is given out, 2 and 3 wait behind the gap and are counted.
  const auto path = write_stream(dir, stream, {{0, ends[0]}, {ends[1], ends[2]}, {ends[2], ends[3]}});
  CaptureCounts counts;
  const auto markers = read_file_markers(path, rule(), &counts);
  ASSERT_EQ(markers.size(), 1u);
  EXPECT_EQ(counts.incomplete_bytes, ends[3] - ends[1]);
}

}  // namespace
}  // namespace m2mlat::markers
