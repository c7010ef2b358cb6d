// A live capture on the loopback interface: real datagrams sent through the kernel, captured with
// nanosecond timestamps on CLOCK_REALTIME between the send and the capture's read. Needs the right
// to capture (root or CAP_NET_RAW); skipped with the reason otherwise.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/packet_markers.hpp"
#include "temp_dir.hpp"

namespace m2mlat::markers {
namespace {

TEST(LiveCapture, LoopbackDatagramsAreStampedBetweenSendAndRead) {
  std::optional<Capture> capture;
  try {
    capture.emplace(Capture::open_live({.interface = "lo"}));
  } catch (const core::Error& e) {
    // No right to capture, or an emulator (qemu-aarch64) without the packet socket's ring.
    GTEST_SKIP() << "no live capture here: " << e.what();
  }
  EXPECT_EQ(capture->stamp_source(), StampSource::host);  // loopback has no adapter clock
  const int sender = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(sender, 0);
  const int receiver = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(receiver, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ASSERT_EQ(::getsockname(receiver, reinterpret_cast<sockaddr*>(&address), &length), 0);
  capture->set_filter("udp dst port " + std::to_string(ntohs(address.sin_port)));
  testing::TempDir dir;
  capture->write_to(dir.file("live.pcap"));

  MarkerOptions options;
  options.rule.key = parse_key_rule("json:seq");
  std::vector<Marker> markers;
  std::vector<std::int64_t> sent_ns;
  for (int i = 0; i < 5; ++i) {
    const std::string message = "{\"seq\":" + std::to_string(i) + "}";
    sent_ns.push_back(core::now_ns(CLOCK_REALTIME));
    ASSERT_EQ(::sendto(sender, message.data(), message.size(), 0, reinterpret_cast<sockaddr*>(&address), sizeof address),
              static_cast<ssize_t>(message.size()));
  }
  const auto deadline = core::monotonic_now() + std::chrono::seconds(5);
  const auto counts = read_markers(*capture, options, [&](Marker&& m) { markers.push_back(std::move(m)); },
                                   [&] { return markers.size() < 5 && core::monotonic_now() < deadline; });
  const auto read_ns = core::now_ns(CLOCK_REALTIME);
  ::close(sender);
  ::close(receiver);
  ASSERT_EQ(markers.size(), 5u);
  EXPECT_EQ(counts.packets, 5u);  // the kernel's filter passed only these
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(markers[i].key, std::to_string(i));
    EXPECT_EQ(markers[i].source, StampSource::host);
    EXPECT_GE(markers[i].time.ns(), sent_ns[i]);
    EXPECT_LE(markers[i].time.ns(), read_ns);
  }
  // The copy written while capturing reads back to the same markers.
  capture.reset();  // closes the copy (flushed)
  capture.emplace(Capture::open_file(dir.file("live.pcap")));
  std::vector<Marker> again;
  read_markers(*capture, options, [&](Marker&& m) { again.push_back(std::move(m)); });
  ASSERT_EQ(again.size(), 5u);
  EXPECT_EQ(again[4].time, markers[4].time);
}

TEST(LiveCapture, UnknownInterfaceIsNoInput) {
  try {
    Capture::open_live({.interface = "m2mlat-none0"});
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("m2mlat-none0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::markers
