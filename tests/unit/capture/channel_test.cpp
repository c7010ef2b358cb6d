// Channel words, the --channel flag, and SIGINT/SIGTERM through the stop descriptor.
#include "m2mlat/capture/channel.hpp"

#include <gtest/gtest.h>
#include <poll.h>

#include <csignal>

#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

TEST(Channel, ParsesTheChannelFlag) {
  const auto a = parse_channel_flag("wheel=pinctrl-rp1:GPIO16");
  EXPECT_EQ(a.name, "wheel");
  EXPECT_EQ(a.chip, "pinctrl-rp1");
  EXPECT_EQ(a.line, "GPIO16");
  EXPECT_EQ(a.edges, Edges::falling);
  EXPECT_EQ(a.debounce.count(), 0);
  const auto b = parse_channel_flag("sync=/dev/gpiochip4:7");
  EXPECT_EQ(b.chip, "/dev/gpiochip4");
  EXPECT_EQ(b.line, "7");
  const auto c = parse_channel_flag("wheel=:16");  // the kmsg source has no chips
  EXPECT_EQ(c.chip, "");
  EXPECT_EQ(c.line, "16");
  for (const char* bad : {"wheel", "=chip:1", "wheel=chip", "wheel=chip:"})
    EXPECT_THROW(parse_channel_flag(bad), core::Error) << bad;
}

TEST(Channel, WordsRoundTrip) {
  for (auto e : {Edges::falling, Edges::rising, Edges::both}) EXPECT_EQ(parse_edges(to_string(e)), e);
  for (auto b : {Bias::as_is, Bias::pull_up, Bias::pull_down, Bias::disabled})
    EXPECT_EQ(parse_bias(to_string(b)), b);
  for (auto k : {EventClock::realtime, EventClock::monotonic, EventClock::hte})
    EXPECT_EQ(parse_event_clock(to_string(k)), k);
  EXPECT_THROW(parse_edges("down"), core::Error);
  EXPECT_EQ(stored_clock(EventClock::realtime), core::Clock::realtime);
  EXPECT_EQ(stored_clock(EventClock::monotonic), core::Clock::monotonic);
}

TEST(StopSignal, ATerminationSignalMakesTheDescriptorReadable) {
  StopSignal stop;
  pollfd fd{stop.fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&fd, 1, 0), 0);
  EXPECT_EQ(stop.take(), "");
  std::raise(SIGTERM);  // blocked while `stop` exists: it waits on the descriptor, the process lives
  EXPECT_EQ(::poll(&fd, 1, 1000), 1);
  EXPECT_EQ(stop.take(), "SIGTERM");
  std::raise(SIGINT);
  EXPECT_EQ(stop.take(), "SIGINT");
}

}  // namespace
}  // namespace m2mlat::capture
