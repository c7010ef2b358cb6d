// The software marker's datagram (m2mlat-mark/1): what is accepted, what is refused and why, the
// written form read back; and the receiving socket on loopback: a real datagram stamped by the kernel
// within the sender's window, a bad one refused with its reason.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>

#include <poll.h>
#include <unistd.h>

#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/mark_datagram.hpp"
#include "m2mlat/markers/mark_receiver.hpp"

namespace m2mlat::markers {
namespace {

TEST(MarkDatagram, AcceptsTheFormatWithOptionalKeyAndSenderTime) {
  auto p = parse_mark("m2mlat-mark/1 planner_out key=812 t=1764000000123456789\n");
  ASSERT_TRUE(p.mark) << p.detail;
  EXPECT_EQ(p.mark->name, "planner_out");
  EXPECT_EQ(p.mark->key, "812");
  EXPECT_EQ(p.mark->sender_ns, 1'764'000'000'123'456'789);
  p = parse_mark("m2mlat-mark/1   /cmd_vel:sent  t=5 key=a-b\r\n");
  ASSERT_TRUE(p.mark) << p.detail;
  EXPECT_EQ(p.mark->name, "/cmd_vel:sent");
  EXPECT_EQ(p.mark->key, "a-b");
  p = parse_mark("m2mlat-mark/1 x");
  ASSERT_TRUE(p.mark);
  EXPECT_TRUE(p.mark->key.empty());
  EXPECT_FALSE(p.mark->sender_ns);
}

TEST(MarkDatagram, RefusesWithAReason) {
  const auto reason = [](std::string_view text) { return std::string(parse_mark(text).reason); };
  EXPECT_EQ(reason(""), "format");
  EXPECT_EQ(reason("m2mlat-mark/2 x"), "format");
  EXPECT_EQ(reason("hello world"), "format");
  EXPECT_EQ(reason("m2mlat-mark/1"), "name");
  EXPECT_EQ(reason("m2mlat-mark/1 bad\x01name"), "name");
  EXPECT_EQ(reason("m2mlat-mark/1 " + std::string(65, 'a')), "name");
  EXPECT_EQ(reason("m2mlat-mark/1 x key="), "key");
  EXPECT_EQ(reason("m2mlat-mark/1 x key=" + std::string(257, 'k')), "key");
  EXPECT_EQ(reason("m2mlat-mark/1 x t=-5"), "time");
  EXPECT_EQ(reason("m2mlat-mark/1 x t=0"), "time");
  EXPECT_EQ(reason("m2mlat-mark/1 x t=12.5"), "time");
  EXPECT_EQ(reason("m2mlat-mark/1 x t=99999999999999999999"), "time");
  EXPECT_EQ(reason("m2mlat-mark/1 x seq=4"), "field");
  EXPECT_EQ(reason("m2mlat-mark/1 x key=1 key=2"), "field");
  EXPECT_EQ(reason("m2mlat-mark/1 x t=1 t=2"), "field");
  EXPECT_EQ(reason("m2mlat-mark/1 x extra"), "field");
  EXPECT_EQ(reason("m2mlat-mark/1 x key=" + std::string(600, 'k')), "size");
  const auto p = parse_mark("m2mlat-mark/1 x t=abc");
  EXPECT_TRUE(p.detail.find("abc") != std::string::npos) << p.detail;
}

TEST(MarkDatagram, WrittenFormReadsBack) {
  MarkDatagram mark{"actuator_cmd", "cmd-7", 1'764'000'000'000'000'001};
  const auto text = format_mark(mark);
  EXPECT_EQ(text, "m2mlat-mark/1 actuator_cmd key=cmd-7 t=1764000000000000001\n");
  EXPECT_EQ(parse_mark(text).mark, mark);
  EXPECT_THROW(format_mark({"bad name", "", std::nullopt}), core::Error);
  EXPECT_THROW(format_mark({"x", "two words", std::nullopt}), core::Error);
}

std::int64_t realtime_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

TEST(MarkReceiver, StampsARealDatagramOnArrivalAndRefusesABadOne) {
  MarkReceiver receiver("127.0.0.1", 0);
  ASSERT_GT(receiver.port(), 0);
  EXPECT_FALSE(receiver.receive());  // nothing waits
  const int sender = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(sender, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(receiver.port()));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto send = [&](const std::string& text) {
    ASSERT_EQ(::sendto(sender, text.data(), text.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(text.size()));
  };
  const auto before = realtime_ns();
  send("m2mlat-mark/1 sent key=9 t=" + std::to_string(before));
  pollfd fd{receiver.fd(), POLLIN, 0};
  ASSERT_EQ(::poll(&fd, 1, 2000), 1);
  auto got = receiver.receive();
  // The window closes when the datagram has been read, not when it became readable: the kernel turns
  // receive stamping on through deferred work after the socket asks for it, and a datagram that
  // arrives before that work ran is stamped as it is read (a loaded CI machine showed this).
  const auto after = realtime_ns();
  send("nonsense");
  ASSERT_TRUE(got);
  ASSERT_TRUE(got->marker) << got->detail;
  const Marker& m = *got->marker;
  EXPECT_EQ(m.name, "sent");
  EXPECT_EQ(m.key, "9");
  EXPECT_EQ(m.sender_time->ns(), before);
  EXPECT_EQ(m.source, receiver.kernel_stamps() ? StampSource::kernel : StampSource::receiver);
  // The kernel stamps the datagram as it reaches the socket (or, see above, as it is read).
  if (receiver.kernel_stamps()) {
    EXPECT_GE(m.time.ns(), before);
    EXPECT_LE(m.time.ns(), after);
  }
  EXPECT_TRUE(m.origin.starts_with("udp 127.0.0.1:")) << m.origin;
  ASSERT_EQ(::poll(&fd, 1, 2000), 1);
  got = receiver.receive();
  ASSERT_TRUE(got);
  EXPECT_FALSE(got->marker);
  EXPECT_EQ(got->reason, "format");
  EXPECT_TRUE(got->detail.starts_with("127.0.0.1:")) << got->detail;
  ::close(sender);
  EXPECT_THROW(MarkReceiver("localhost", 0), core::Error);  // numeric addresses only
}

}  // namespace
}  // namespace m2mlat::markers
