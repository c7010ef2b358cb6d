// The GPIO source against the in-process twin of the character device: lookup, request settings,
// exact timestamps and sequence numbers, loss on buffer overflow, and the errors' advice.
#include "m2mlat/capture/gpio_source.hpp"

#include <gtest/gtest.h>

#include "m2mlat/capture/chip_lookup.hpp"
#include "m2mlat/capture/fake_gpio.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

class GpioSourceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    other_ = gpio_.add_chip("gpio-brcmstb@107d508500", 4);
    std::vector<std::string> names;
    for (int i = 0; i < 28; ++i) names.push_back("GPIO" + std::to_string(i));
    rp1_ = gpio_.add_chip("pinctrl-rp1", 54, names);
  }
  ChannelSpec wheel(std::string line = "GPIO16") {
    ChannelSpec spec;
    spec.name = "wheel";
    spec.chip = "pinctrl-rp1";
    spec.line = std::move(line);
    return spec;
  }
  std::string message_of(const std::vector<ChannelSpec>& specs, core::ErrorKind* kind = nullptr) {
    try {
      GpioSource source(gpio_, specs, {"vehicle"});
    } catch (const core::Error& e) {
      if (kind != nullptr) *kind = e.kind();
      return e.what();
    }
    return {};
  }
  FakeGpio gpio_;
  std::string other_, rp1_;
};

TEST_F(GpioSourceTest, FindsChipsByPathNameAndLabelAndLinesByOffsetAndName) {
  EXPECT_EQ(find_chip(gpio_, "pinctrl-rp1").path, rp1_);
  EXPECT_EQ(find_chip(gpio_, "gpiochip1").path, rp1_);
  EXPECT_EQ(find_chip(gpio_, rp1_).label, "pinctrl-rp1");
  const auto chip = find_chip(gpio_, "pinctrl-rp1");
  EXPECT_EQ(find_line(gpio_, chip, "GPIO16"), 16u);
  EXPECT_EQ(find_line(gpio_, chip, "16"), 16u);
  EXPECT_THROW(find_line(gpio_, chip, "54"), core::Error);
  EXPECT_THROW(find_line(gpio_, chip, "GPIO99"), core::Error);
}

TEST_F(GpioSourceTest, RequestsTheLineWithItsSettingsAndTheLargestBuffer) {
  auto spec = wheel();
  spec.bias = Bias::pull_up;
  GpioSource source(gpio_, {spec}, {"vehicle"});
  const auto info = gpio_.line_info(rp1_, 16);
  EXPECT_TRUE(info.used());
  EXPECT_EQ(info.consumer, "m2mlat-wheel");
  EXPECT_NE(info.flags & GPIO_V2_LINE_FLAG_EDGE_FALLING, 0u);
  EXPECT_EQ(info.flags & GPIO_V2_LINE_FLAG_EDGE_RISING, 0u);
  EXPECT_NE(info.flags & GPIO_V2_LINE_FLAG_BIAS_PULL_UP, 0u);
  EXPECT_NE(info.flags & GPIO_V2_LINE_FLAG_EVENT_CLOCK_REALTIME, 0u);
  EXPECT_EQ(info.debounce_us, 0u);
  const auto request = make_input_request(spec, 16, "m2mlat-wheel", kMaxEventBufferSize);
  EXPECT_EQ(request.event_buffer_size, 1024u);
  EXPECT_EQ(request.config.num_attrs, 0u);  // no debounce attribute by default
  EXPECT_TRUE(source.warnings().empty());
  EXPECT_EQ(source.consumers(), std::vector<std::string>{"m2mlat-wheel"});
}

TEST_F(GpioSourceTest, EventsKeepTheKernelTimestampAndSequenceNumbersExactly) {
  GpioSource source(gpio_, {wheel()}, {"vehicle"});
  const std::uint64_t stamps[] = {1762872545550296135ULL, 1762872545550296136ULL, 1762872546000000001ULL};
  for (auto ns : stamps) {
    gpio_.edge(rp1_, 16, true, ns - 7);  // rising: not watched
    gpio_.edge(rp1_, 16, false, ns);
  }
  ReadResult result;
  source.read(result, 100);
  ASSERT_EQ(result.events.size(), 3u);
  EXPECT_TRUE(result.gaps.empty());
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& e = result.events[i];
    EXPECT_EQ(e.node, "vehicle");
    EXPECT_EQ(e.channel, "wheel");
    EXPECT_EQ(e.edge, core::Edge::falling);
    EXPECT_EQ(e.time, core::TimePoint::from_ns(core::Clock::realtime, static_cast<std::int64_t>(stamps[i])));
    EXPECT_EQ(e.seqno, i + 1);
    EXPECT_EQ(e.line_seqno, i + 1);
  }
}

TEST_F(GpioSourceTest, ActiveLowInvertsAndBothEdgesAreReported) {
  auto spec = wheel();
  spec.edges = Edges::rising;
  spec.active_low = true;
  GpioSource source(gpio_, {spec}, {"vehicle"});
  EXPECT_EQ(gpio_.edge(rp1_, 16, false, 100), 1);  // physical falling = logical rising
  EXPECT_EQ(gpio_.edge(rp1_, 16, true, 200), 0);
  ReadResult result;
  source.read(result, 10);
  ASSERT_EQ(result.events.size(), 1u);
  EXPECT_EQ(result.events[0].edge, core::Edge::rising);
}

TEST_F(GpioSourceTest, AStalledReaderSeesTheExactLossTheKernelReports) {
  auto spec = wheel();
  GpioSource source(gpio_, {spec}, {"vehicle", "m2mlat-", 16});
  for (std::uint64_t i = 1; i <= 50; ++i) gpio_.edge(rp1_, 16, false, i * 1000);
  ReadResult result;
  source.read(result, 1000);
  // 16 buffered; the oldest 34 were dropped: seqnos 1..34 are missing.
  ASSERT_EQ(result.events.size(), 16u);
  ASSERT_EQ(result.gaps.size(), 1u);
  EXPECT_EQ(result.gaps[0], (Gap{"wheel", "seqno_gap", 1, 34}));
  EXPECT_EQ(result.events.front().seqno, 35u);
  EXPECT_EQ(gpio_.events_dropped(), 34u);
  // Later overflows again: counted from the last seen seqno.
  for (std::uint64_t i = 51; i <= 70; ++i) gpio_.edge(rp1_, 16, false, i * 1000);
  result.clear();
  source.read(result, 1000);
  ASSERT_EQ(result.gaps.size(), 1u);
  EXPECT_EQ(result.gaps[0], (Gap{"wheel", "seqno_gap", 51, 4}));
  EXPECT_EQ(result.events.size(), 16u);
}

TEST_F(GpioSourceTest, ReadsInBatchesAcrossChannels) {
  auto a = wheel("GPIO16");
  auto b = wheel("GPIO17");
  b.name = "pedal";
  GpioSource source(gpio_, {a, b}, {"vehicle"});
  for (std::uint64_t i = 1; i <= 10; ++i) {
    gpio_.edge(rp1_, 16, false, i);
    gpio_.edge(rp1_, 17, false, i);
  }
  ReadResult result;
  source.read(result, 15);
  EXPECT_EQ(result.events.size(), 15u);
  source.read(result, 15);
  EXPECT_EQ(result.events.size(), 20u);
  EXPECT_TRUE(result.gaps.empty());
}

TEST_F(GpioSourceTest, DebounceIsPassedToTheKernelAndWarnedAbout) {
  auto spec = wheel();
  spec.debounce = std::chrono::microseconds(500);
  GpioSource source(gpio_, {spec}, {"vehicle"});
  EXPECT_EQ(gpio_.line_info(rp1_, 16).debounce_us, 500u);
  ASSERT_EQ(source.warnings().size(), 1u);
  EXPECT_NE(source.warnings()[0].find("late"), std::string::npos);
}

TEST_F(GpioSourceTest, ErrorsSayWhatToDo) {
  core::ErrorKind kind{};
  gpio_.hold_line(rp1_, 16, "gpiomon");
  auto busy = message_of({wheel()}, &kind);
  EXPECT_NE(busy.find("in use by 'gpiomon'"), std::string::npos) << busy;
  EXPECT_EQ(kind, core::ErrorKind::io);

  auto missing = wheel();
  missing.chip = "pinctrl-rp2";
  const auto no_chip = message_of({missing}, &kind);
  EXPECT_NE(no_chip.find("gpiochip1 (pinctrl-rp1)"), std::string::npos) << no_chip;
  EXPECT_EQ(kind, core::ErrorKind::no_input);

  gpio_.deny_access(rp1_);
  const auto denied = message_of({wheel()}, &kind);
  EXPECT_NE(denied.find("permission denied"), std::string::npos) << denied;
  EXPECT_NE(denied.find("udev"), std::string::npos) << denied;

  FakeGpio none;
  try {
    find_chip(none, "pinctrl-rp1");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no GPIO chips at all"), std::string::npos);
  }
}

TEST_F(GpioSourceTest, ALineIsReleasedWhenTheSourceGoes) {
  { GpioSource source(gpio_, {wheel()}, {"vehicle"}); }
  EXPECT_FALSE(gpio_.line_info(rp1_, 16).used());
  GpioSource again(gpio_, {wheel()}, {"vehicle"});
  EXPECT_TRUE(gpio_.line_info(rp1_, 16).used());
}

}  // namespace
}  // namespace m2mlat::capture
