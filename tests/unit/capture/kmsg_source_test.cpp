// The kernel-log source following a growing file: GPIO lines become events with their exact
// timestamps, kmsg sequence jumps become losses, other lines are passed over.
#include "m2mlat/capture/kmsg_source.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

class KmsgSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() / ("m2mlat-kmsg-" + std::to_string(::getpid()) + ".log"))
                .string();
    std::ofstream(path_, std::ios::trunc).flush();
  }
  void TearDown() override { std::filesystem::remove(path_); }
  void append(const std::string& text) { std::ofstream(path_, std::ios::app) << text; }
  std::string path_;
};

TEST_F(KmsgSourceTest, FollowsAFileAndKeepsTheModulesTimestamps) {
  ChannelSpec wheel;
  wheel.name = "wheel";
  wheel.line = "GPIO16";
  KmsgSource source({"operator", path_, {wheel}});
  EXPECT_EQ(source.fd(), -1);  // a file cannot be polled: read on an interval
  append("6,100,5000,-;GPIO_16_IRQ:1762872545550296135\n6,101,5001,-;usb 1-1: new device\n6,102,50");
  ReadResult out;
  source.read(out, 100);
  ASSERT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].time.ns(), 1762872545550296135);
  EXPECT_EQ(out.events[0].channel, "wheel");
  EXPECT_EQ(out.events[0].node, "operator");
  EXPECT_EQ(out.events[0].flags, core::kFlagNoKernelSeqno);
  EXPECT_TRUE(out.gaps.empty());
  // The rest of the unfinished line arrives, then records 103..106 are missing.
  append(
      "02,-;GPIO_16_IRQ:1762872546000000000\n6,107,5100,-;GPIO_17_IRQ:1\n6,108,5101,-;GPIO_16_IRQ:"
      "1762872547000000000\n");
  out.clear();
  source.read(out, 100);
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_EQ(out.events[0].time.ns(), 1762872546000000000);
  EXPECT_EQ(out.events[1].time.ns(), 1762872547000000000);
  ASSERT_EQ(out.gaps.size(), 1u);
  EXPECT_EQ(out.gaps[0], (Gap{"", "kmsg_gap", 103, 4}));
  ASSERT_EQ(source.notes().size(), 1u);  // pin 17 is no channel's
}

TEST_F(KmsgSourceTest, WithoutChannelsEveryPinIsItsOwnChannelAndMalformedLinesAreNoted) {
  KmsgSource source({"operator", path_, {}});
  append("[  12.345678] GPIO_16_IRQ:5\n[  12.345679] GPIO_4_IRQ:6\n[  12.4] GPIO_16_IRQ:12ab\n");
  ReadResult out;
  source.read(out, 100);
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_EQ(out.events[0].channel, "gpio16");
  EXPECT_EQ(out.events[1].channel, "gpio4");
  ASSERT_EQ(source.notes().size(), 1u);
  EXPECT_NE(source.notes()[0].find("line 3"), std::string::npos) << source.notes()[0];
}

TEST_F(KmsgSourceTest, ALineLongerThanTheLimitIsPassedOverNotHeld) {
  KmsgSource source({"operator", path_, {}});
  ReadResult out;
  // 200 KiB without a newline, written in pieces: never held whole, and its end is passed over too.
  append("[  1.0] GPIO_16_IRQ:5\n");
  for (int i = 0; i < 25; ++i) {
    append(std::string(8192, 'x'));
    source.read(out, 100);
  }
  append("GPIO_16_IRQ:99\n[  1.1] GPIO_16_IRQ:7\n");
  source.read(out, 100);
  ASSERT_EQ(out.events.size(), 2u);
  EXPECT_EQ(out.events[0].time.ns(), 5);
  EXPECT_EQ(out.events[1].time.ns(), 7);  // not the 99 at the long line's end
  ASSERT_EQ(source.notes().size(), 1u);
  EXPECT_NE(source.notes()[0].find("line 2: longer than 65536 bytes"), std::string::npos)
      << source.notes()[0];
}

TEST_F(KmsgSourceTest, PinsAndErrors) {
  std::uint32_t pin = 0;
  EXPECT_TRUE(KmsgSource::pin_of("GPIO16", pin));
  EXPECT_EQ(pin, 16u);
  EXPECT_TRUE(KmsgSource::pin_of("4", pin));
  EXPECT_FALSE(KmsgSource::pin_of("GPIO", pin));
  ChannelSpec bad;
  bad.name = "wheel";
  bad.line = "wheel-sensor";
  EXPECT_THROW(KmsgSource({"n", path_, {bad}}), core::Error);
  try {
    KmsgSource source({"n", "/nonexistent/kern.log", {}});
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
  }
}

}  // namespace
}  // namespace m2mlat::capture
