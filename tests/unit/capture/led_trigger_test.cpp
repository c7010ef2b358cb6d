// The glass-to-glass LED on the GPIO twin: the flash schedule, the command and edge triggers, and the
// events a switch is recorded as (time in the middle of the clock readings around the ioctl).
#include "m2mlat/capture/led_trigger.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/capture/fake_gpio.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture::led_trigger_test {
namespace {

constexpr std::int64_t kMs = 1'000'000;

PulseOptions led_options(core::Duration on_for = core::Duration{0}) {
  PulseOptions o;
  o.chip = "vehicle-board";
  o.line = "led";
  o.consumer = "m2mlat-led";
  o.on_for = on_for;
  return o;
}

// An eventfd that the test sets from a callback to end a run.
struct StopFd {
  int fd = ::eventfd(0, EFD_CLOEXEC);
  ~StopFd() { ::close(fd); }
  void set() const {
    const std::uint64_t one = 1;
    EXPECT_EQ(::write(fd, &one, sizeof one), static_cast<ssize_t>(sizeof one));
  }
};

TEST(LedSchedule, FlashesOnMultiplesOfThePeriodAndSwitchesOffOnForLater) {
  FakeGpio gpio;
  const auto chip = gpio.add_chip("vehicle-board", 4, {"hall", "led"});
  auto options = led_options(core::Duration{3 * kMs});
  options.period = core::Duration{10 * kMs};
  options.count = 6;  // three flashes
  std::vector<PulseEdge> edges;
  {
    PulseGenerator led(gpio, options);
    EXPECT_EQ(gpio.line_info(chip, 1).consumer, "m2mlat-led");
    led.run(-1, [&](const PulseEdge& e) { edges.push_back(e); });
  }
  ASSERT_EQ(edges.size(), 6u);
  EXPECT_EQ(edges[0].deadline.ns() % (10 * kMs), 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(edges[i].edge, i % 2 == 0 ? core::Edge::rising : core::Edge::falling);
    const std::int64_t expected =
        static_cast<std::int64_t>(i / 2) * 10 * kMs + static_cast<std::int64_t>(i % 2) * 3 * kMs;
    EXPECT_EQ(edges[i].deadline.ns() - edges[0].deadline.ns(), expected) << i;
    EXPECT_GE(edges[i].commanded, edges[i].deadline);
    EXPECT_GE(edges[i].after, edges[i].commanded);  // the bound is an interval, never negative
  }
  const auto& changes = gpio.output_changes();
  ASSERT_EQ(changes.size(), 7u);  // six switches and the final low
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(changes[i].value, i % 2 == 0);
}

TEST(LedSchedule, AnOnTimeNotShorterThanThePeriodIsRefused) {
  FakeGpio gpio;
  gpio.add_chip("vehicle-board", 4, {"hall", "led"});
  auto options = led_options(core::Duration{10 * kMs});
  options.period = core::Duration{10 * kMs};
  try {
    PulseGenerator led(gpio, options);
    FAIL() << "accepted --on-for equal to --period";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("--on-for"), std::string::npos);
  }
}

TEST(LedEvent, TakesTheMiddleOfTheReadingsAroundTheIoctl) {
  PulseEdge edge{3, core::Edge::rising, core::TimePoint::from_ns(core::Clock::realtime, 1000),
                 core::TimePoint::from_ns(core::Clock::realtime, 5000),
                 core::TimePoint::from_ns(core::Clock::realtime, 5801)};
  EXPECT_EQ(edge.bound(), core::Duration{801});
  const auto e = led_event("vehicle", "led", edge);
  EXPECT_EQ(e.node, "vehicle");
  EXPECT_EQ(e.channel, "led");
  EXPECT_EQ(e.edge, core::Edge::rising);
  EXPECT_EQ(e.time.ns(), 5400);  // 5000 + 801 / 2
  EXPECT_EQ(e.flags, core::kFlagCommanded | core::kFlagNoKernelSeqno);
}

TEST(LedAction, ParsesTheThreeWordsAndAnEmptyLine) {
  EXPECT_EQ(parse_led_action("on"), LedAction::on);
  EXPECT_EQ(parse_led_action(" off\r"), LedAction::off);
  EXPECT_EQ(parse_led_action("flash"), LedAction::flash);
  EXPECT_EQ(parse_led_action(""), LedAction::flash);
  EXPECT_FALSE(parse_led_action("blink"));
  EXPECT_FALSE(parse_led_action("ON"));
}

TEST(LedStream, SwitchesAsTheLinesSayAndNamesARefusedLine) {
  FakeGpio gpio;
  gpio.add_chip("vehicle-board", 4, {"hall", "led"});
  PulseGenerator led(gpio, led_options());
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const std::string commands = "on\non\nblink\noff\nflash";  // the last line without its newline
  ASSERT_EQ(::write(pipe_fds[1], commands.data(), commands.size()), static_cast<ssize_t>(commands.size()));
  ::close(pipe_fds[1]);
  auto trigger = stream_trigger(pipe_fds[0], "stdin");
  std::vector<PulseEdge> edges;
  std::vector<std::string> refused;
  const auto summary = run_triggered(
      led, *trigger, core::Duration{4 * kMs}, -1, [&](const PulseEdge& e) { edges.push_back(e); },
      [&](const TriggerInput& in) { refused.insert(refused.end(), in.refused.begin(), in.refused.end()); });
  ::close(pipe_fds[0]);
  EXPECT_EQ(summary.stop_reason, "end of input");
  EXPECT_EQ(summary.triggers, 4u);  // on, on, off, flash
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0], "stdin line 3: unknown LED command 'blink' (on, off, flash)");
  // on, (on again: nothing), off, flash on, flash off after 4 ms
  ASSERT_EQ(edges.size(), 4u);
  EXPECT_EQ(edges[0].edge, core::Edge::rising);
  EXPECT_EQ(edges[1].edge, core::Edge::falling);
  EXPECT_EQ(edges[2].edge, core::Edge::rising);
  EXPECT_EQ(edges[3].edge, core::Edge::falling);
  EXPECT_EQ(edges[3].deadline - edges[2].deadline, core::Duration{4 * kMs});
  EXPECT_GE(edges[3].commanded, edges[3].deadline);
  for (std::size_t i = 0; i < edges.size(); ++i) EXPECT_EQ(edges[i].index, i);
  EXPECT_FALSE(led.high());
}

TEST(LedDatagram, AFlashPerDatagramOnLoopback) {
  FakeGpio gpio;
  gpio.add_chip("vehicle-board", 4, {"hall", "led"});
  PulseGenerator led(gpio, led_options());
  DatagramTrigger trigger("127.0.0.1:0");
  ASSERT_GT(trigger.port(), 0);
  EXPECT_EQ(trigger.describe(), "commands as UDP datagrams on 127.0.0.1:" + std::to_string(trigger.port()));
  const int sender = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(trigger.port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (const std::string word : {"flash", "nonsense"})
    ASSERT_EQ(
        ::sendto(sender, word.data(), word.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to),
        static_cast<ssize_t>(word.size()));
  ::close(sender);
  StopFd stop;
  std::vector<PulseEdge> edges;
  std::vector<std::string> refused;
  const auto summary = run_triggered(
      led, trigger, core::Duration{2 * kMs}, stop.fd,
      [&](const PulseEdge& e) {
        edges.push_back(e);
        if (e.edge == core::Edge::falling) stop.set();
      },
      [&](const TriggerInput& in) { refused.insert(refused.end(), in.refused.begin(), in.refused.end()); },
      [] { return std::string("test"); });
  EXPECT_EQ(summary.stop_reason, "test");
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[0].edge, core::Edge::rising);
  EXPECT_EQ(edges[1].deadline - edges[0].deadline, core::Duration{2 * kMs});
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_NE(refused[0].find("datagram from 127.0.0.1:"), std::string::npos);
  EXPECT_NE(refused[0].find("'nonsense'"), std::string::npos);
}

TEST(LedDatagram, AMalformedAddressIsAUsageError) {
  for (const std::string bad : {"9120", "localhost:9120", "127.0.0.1:70000", "127.0.0.1:x"}) {
    try {
      DatagramTrigger trigger(bad);
      FAIL() << bad;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage) << bad;
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

TEST(LedEdge, EachInputEdgeFlashesAndIsReturnedWithItsKernelStamp) {
  FakeGpio gpio;
  const auto chip = gpio.add_chip("vehicle-board", 4, {"hall", "led"});
  PulseGenerator led(gpio, led_options());
  ChannelSpec hall;
  hall.name = "wheel";
  hall.chip = "vehicle-board";
  hall.line = "hall";
  auto trigger = edge_trigger(gpio, hall, "vehicle");
  // Two edges before the run: both are read in one take, the second only extends the first's flash.
  ASSERT_EQ(gpio.edge(chip, 0, false, 1'000), 1);
  ASSERT_EQ(gpio.edge(chip, 0, true, 2'000), 0);  // a rising edge: not watched
  ASSERT_EQ(gpio.edge(chip, 0, false, 3'000), 1);
  StopFd stop;
  std::vector<PulseEdge> edges;
  std::vector<core::Event> seen;
  const auto summary = run_triggered(
      led, *trigger, core::Duration{3 * kMs}, stop.fd,
      [&](const PulseEdge& e) {
        edges.push_back(e);
        if (e.edge == core::Edge::falling) stop.set();
      },
      [&](const TriggerInput& in) { seen.insert(seen.end(), in.edges.begin(), in.edges.end()); },
      [] { return std::string("test"); });
  EXPECT_EQ(summary.triggers, 2u);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].node, "vehicle");
  EXPECT_EQ(seen[0].channel, "wheel");
  EXPECT_EQ(seen[0].time.ns(), 1'000);
  EXPECT_EQ(seen[1].time.ns(), 3'000);
  EXPECT_EQ(seen[1].seqno, 2u);
  ASSERT_EQ(edges.size(), 2u);  // one flash: on, then off 3 ms after the last trigger
  EXPECT_EQ(edges[0].edge, core::Edge::rising);
  EXPECT_EQ(edges[1].edge, core::Edge::falling);
  // The flash ends on_for after the trigger was seen (the on edge's deadline), not after the on write
  // returned: how long reading the trigger and the write took does not lengthen the flash.
  EXPECT_EQ(edges[1].deadline - edges[0].deadline, core::Duration{3 * kMs});
  EXPECT_GE(edges[1].commanded - edges[0].deadline, core::Duration{3 * kMs});
  EXPECT_LE(edges[0].deadline.ns(), edges[0].commanded.ns());
  const auto& changes = gpio.output_changes();
  ASSERT_GE(changes.size(), 2u);
  EXPECT_EQ(changes[0].offset, 1u);
  EXPECT_TRUE(changes[0].value);
}

}  // namespace
}  // namespace m2mlat::capture::led_trigger_test
