// The pulse generator on the twin: alternating output values on a fixed absolute schedule.
#include "m2mlat/capture/pulse.hpp"

#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <vector>

#include "m2mlat/capture/fake_gpio.hpp"

namespace m2mlat::capture {
namespace {

TEST(Pulse, TogglesOnMultiplesOfThePeriodAndLeavesTheLineLow) {
  FakeGpio gpio;
  const auto chip = gpio.add_chip("gpio-sim.0-node1", 8, {"a", "b", "sync-out"});
  std::vector<PulseEdge> edges;
  PulseSummary summary;
  {
    PulseOptions options;
    options.chip = "gpio-sim.0-node1";
    options.line = "sync-out";
    options.period = std::chrono::milliseconds(5);
    options.count = 6;
    PulseGenerator generator(gpio, options);
    EXPECT_EQ(gpio.line_info(chip, 2).consumer, "m2mlat-pulse");
    EXPECT_NE(gpio.line_info(chip, 2).flags & GPIO_V2_LINE_FLAG_OUTPUT, 0u);
    summary = generator.run(-1, [&](const PulseEdge& e) { edges.push_back(e); });
  }
  EXPECT_EQ(summary.stop_reason, "count");
  ASSERT_EQ(summary.edges, 6u);
  ASSERT_EQ(edges.size(), 6u);
  const std::int64_t period = 5'000'000;
  EXPECT_EQ(edges[0].deadline.ns() % period, 0);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(edges[i].index, i);
    EXPECT_EQ(edges[i].edge, i % 2 == 0 ? core::Edge::rising : core::Edge::falling);
    EXPECT_EQ(edges[i].deadline.ns() - edges[0].deadline.ns(), static_cast<std::int64_t>(i) * period);
    EXPECT_GE(edges[i].commanded, edges[i].deadline);  // never before its deadline
  }
  const auto& changes = gpio.output_changes();
  ASSERT_EQ(changes.size(), 7u);  // six toggles and the final low
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(changes[i].offset, 2u);
    EXPECT_EQ(changes[i].value, i % 2 == 0);
  }
  EXPECT_FALSE(changes.back().value);
  EXPECT_FALSE(gpio.line_info(chip, 2).used());

  const auto event = commanded_event("pulser", edges[1]);
  EXPECT_EQ(event.node, "pulser");
  EXPECT_EQ(event.channel, "pulse");
  EXPECT_EQ(event.edge, core::Edge::falling);
  EXPECT_EQ(event.time, edges[1].commanded);
  EXPECT_EQ(event.flags, core::kFlagCommanded | core::kFlagNoKernelSeqno);
}

TEST(Pulse, AStopBeforeTheFirstDeadlineMakesNoEdge) {
  FakeGpio gpio;
  gpio.add_chip("gpio-sim.0-node1", 4);
  PulseOptions options;
  options.chip = "gpiochip0";
  options.line = "1";
  PulseGenerator generator(gpio, options);
  const int stop = ::eventfd(1, EFD_CLOEXEC);
  const auto summary = generator.run(stop, {}, [] { return std::string("SIGINT"); });
  ::close(stop);
  EXPECT_EQ(summary.edges, 0u);
  EXPECT_EQ(summary.stop_reason, "SIGINT");
}

}  // namespace
}  // namespace m2mlat::capture
