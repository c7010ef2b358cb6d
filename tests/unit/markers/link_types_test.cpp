// Every link type m2mlat decodes, in pcap files written by libpcap's own writer, and the pcapng
// layout written byte by byte; an unknown link type and a truncated file fail with the file named.
#include <gtest/gtest.h>
#include <pcap/pcap.h>

#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/capture_writer.hpp"
#include "m2mlat/markers/packet_markers.hpp"
#include "temp_dir.hpp"

namespace m2mlat::markers {
namespace {

constexpr std::int64_t kT0 = 1'764'000'000'123'456'789;  // ns, CLOCK_REALTIME

MarkerOptions stamp_rule() {
  MarkerOptions options;
  options.rule.key = parse_key_rule("json:seq");
  options.rule.sender_ms = "stamp";
  options.node = "vehicle";
  return options;
}

std::string command(int seq) { return "{\"seq\":" + std::to_string(seq) + ",\"stamp\":1764000000100,\"steer\":0.25}"; }

struct LinkCase {
  int link_type;
  const char* source;
  const char* destination;
};

class LinkTypes : public ::testing::TestWithParam<LinkCase> {};

TEST_P(LinkTypes, UdpCommandsBecomeMarkersWithTheirCaptureTime) {
  testing::TempDir dir;
  const auto path = dir.file("c.pcap");
  const auto [link_type, source, destination] = GetParam();
  {
    CaptureWriter writer(path, link_type);
    const auto flow = make_flow(Transport::udp, source, 40000, destination, 5000);
    for (int i = 0; i < 3; ++i) writer.write(kT0 + i * 10'000'001, build_frame(link_type, flow, bytes_of(command(i))));
  }
  CaptureCounts counts;
  const auto markers = read_file_markers(path, stamp_rule(), &counts);
  ASSERT_EQ(markers.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(markers[i].key, std::to_string(i));
    EXPECT_EQ(markers[i].time.ns(), kT0 + i * 10'000'001);  // nanoseconds kept exactly
    EXPECT_EQ(markers[i].time.clock(), core::Clock::realtime);
    ASSERT_TRUE(markers[i].sender_time.has_value());
    EXPECT_EQ(markers[i].sender_time->ns(), 1'764'000'000'100'000'000);
    EXPECT_EQ(markers[i].node, "vehicle");
    EXPECT_EQ(markers[i].source, StampSource::file);
  }
  EXPECT_NE(markers[0].origin.find("c.pcap#1 udp "), std::string::npos) << markers[0].origin;
  EXPECT_EQ(counts.packets, 3u);
  EXPECT_EQ(counts.messages, 3u);
  EXPECT_EQ(counts.other + counts.malformed + counts.snapped, 0u);
}

INSTANTIATE_TEST_SUITE_P(All, LinkTypes,
                         ::testing::Values(LinkCase{DLT_EN10MB, "10.0.0.1", "10.0.0.2"},
                                           LinkCase{DLT_EN10MB, "fd00::1", "fd00::2"},
                                           LinkCase{DLT_LINUX_SLL, "10.0.0.1", "10.0.0.2"},
                                           LinkCase{DLT_LINUX_SLL2, "10.0.0.1", "10.0.0.2"},
                                           LinkCase{DLT_RAW, "10.0.0.1", "10.0.0.2"},
                                           LinkCase{DLT_RAW, "fd00::1", "fd00::2"},
                                           LinkCase{DLT_IPV4, "10.0.0.1", "10.0.0.2"},
                                           LinkCase{DLT_NULL, "127.0.0.1", "127.0.0.1"},
                                           LinkCase{DLT_NULL, "::1", "::1"},
                                           LinkCase{DLT_LOOP, "127.0.0.1", "127.0.0.1"}));

TEST(LinkTypes, EthernetVlanTagAndPaddingAreSkipped) {
  testing::TempDir dir;
  const auto path = dir.file("vlan.pcap");
  {
    CaptureWriter writer(path, DLT_EN10MB);
    auto frame = build_frame(DLT_EN10MB, make_flow(Transport::udp, "10.0.0.1", 1, "10.0.0.2", 2), bytes_of(command(7)));
    // An 802.1Q tag (TPID 0x8100, VLAN 5) before the ethertype, and trailing padding.
    frame.insert(frame.begin() + 12, {0x81, 0x00, 0x00, 0x05});
    frame.insert(frame.end(), 6, 0);
    writer.write(kT0, frame);
  }
  const auto markers = read_file_markers(path, stamp_rule());
  ASSERT_EQ(markers.size(), 1u);
  EXPECT_EQ(markers[0].key, "7");
}

TEST(LinkTypes, UnknownLinkTypeNamesTheFileAndTheType) {
  testing::TempDir dir;
  const auto path = dir.file("wifi.pcap");
  {
    CaptureWriter writer(path, DLT_IEEE802_11);
    writer.write(kT0, std::vector<std::uint8_t>(40, 0));
  }
  try {
    read_file_markers(path, stamp_rule());
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("link type 105 IEEE802_11"), std::string::npos) << what;
  }
}

TEST(LinkTypes, TruncatedFileNamesThePacketAndKeepsThoseBefore) {
  testing::TempDir dir;
  const auto path = dir.file("cut.pcap");
  {
    CaptureWriter writer(path, DLT_RAW);
    const auto flow = make_flow(Transport::udp, "10.0.0.1", 1, "10.0.0.2", 2);
    for (int i = 0; i < 5; ++i) writer.write(kT0 + i, build_frame(DLT_RAW, flow, bytes_of(command(i))));
  }
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 10);  // packet 5 loses its end
  auto capture = Capture::open_file(path);
  std::vector<Marker> markers;
  try {
    read_markers(capture, stamp_rule(), [&](Marker&& m) { markers.push_back(std::move(m)); });
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    const std::string what = e.what();
    EXPECT_NE(what.find(path + ": packet 5:"), std::string::npos) << what;
    EXPECT_NE(what.find("truncated"), std::string::npos) << what;
  }
  EXPECT_EQ(markers.size(), 4u);  // the packets before the cut were read
}

TEST(LinkTypes, NotACaptureFileAndAMissingFile) {
  testing::TempDir dir;
  const auto path = dir.file("text.pcap");
  std::ofstream(path) << "node,time\n";
  try {
    Capture::open_file(path);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  try {
    Capture::open_file(dir.file("missing.pcap"));
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
  }
}

// pcapng, as Wireshark and recent tcpdump write it: a section header, an interface description with
// if_tsresol = 9 (nanoseconds), enhanced packet blocks. Written byte by byte (little-endian).
void put32le(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
}
void put16le(std::string& out, std::uint16_t v) {
  out.push_back(static_cast<char>(v));
  out.push_back(static_cast<char>(v >> 8));
}
void block(std::string& out, std::uint32_t type, const std::string& body) {
  const auto length = static_cast<std::uint32_t>(12 + body.size());
  put32le(out, type);
  put32le(out, length);
  out += body;
  put32le(out, length);
}

TEST(LinkTypes, PcapngWithNanosecondResolution) {
  testing::TempDir dir;
  const auto path = dir.file("c.pcapng");
  std::string file;
  std::string shb;
  put32le(shb, 0x1A2B3C4D);
  put16le(shb, 1);
  put16le(shb, 0);
  put32le(shb, 0xFFFFFFFF);
  put32le(shb, 0xFFFFFFFF);  // section length unknown
  block(file, 0x0A0D0D0A, shb);
  std::string idb;
  put16le(idb, 101);  // LINKTYPE_RAW
  put16le(idb, 0);
  put32le(idb, 0);  // snaplen: no limit
  put16le(idb, 9);  // if_tsresol
  put16le(idb, 1);
  idb += std::string("\x09\0\0\0", 4);  // 10^-9, padded to 4 bytes
  put32le(idb, 0);  // opt_endofopt
  block(file, 1, idb);
  const auto flow = make_flow(Transport::udp, "10.0.0.1", 1, "10.0.0.2", 2);
  for (int i = 0; i < 2; ++i) {
    const auto frame = build_frame(DLT_RAW, flow, bytes_of(command(i)));
    const auto t = static_cast<std::uint64_t>(kT0 + i * 1'000'001);
    std::string epb;
    put32le(epb, 0);  // interface 0
    put32le(epb, static_cast<std::uint32_t>(t >> 32));
    put32le(epb, static_cast<std::uint32_t>(t));
    put32le(epb, static_cast<std::uint32_t>(frame.size()));
    put32le(epb, static_cast<std::uint32_t>(frame.size()));
    epb.append(frame.begin(), frame.end());
    epb.append((4 - frame.size() % 4) % 4, '\0');
    block(file, 6, epb);
  }
  std::ofstream(path, std::ios::binary) << file;
  const auto markers = read_file_markers(path, stamp_rule());
  ASSERT_EQ(markers.size(), 2u);
  EXPECT_EQ(markers[0].time.ns(), kT0);
  EXPECT_EQ(markers[1].time.ns(), kT0 + 1'000'001);
  EXPECT_EQ(markers[1].key, "1");
}

TEST(LinkTypes, FilterPassesOnlyTheCommandsAndIndexesStayTheFiles) {
  testing::TempDir dir;
  const auto path = dir.file("mixed.pcap");
  {
    CaptureWriter writer(path, DLT_EN10MB);
    for (int i = 0; i < 4; ++i) {
      const std::uint16_t port = i % 2 == 0 ? 5000 : 6000;
      writer.write(kT0 + i,
                   build_frame(DLT_EN10MB, make_flow(Transport::udp, "10.0.0.1", 1, "10.0.0.2", port), bytes_of(command(i))));
    }
  }
  auto options = stamp_rule();
  options.rule.filter = "udp dst port 6000";
  const auto markers = read_file_markers(path, options);
  ASSERT_EQ(markers.size(), 2u);
  EXPECT_EQ(markers[0].key, "1");
  EXPECT_NE(markers[1].origin.find("mixed.pcap#4 "), std::string::npos) << markers[1].origin;
  options.rule.filter = "udp port nonsense";
  try {
    read_file_markers(path, options);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("filter 'udp port nonsense'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::markers
