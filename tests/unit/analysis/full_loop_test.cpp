// The full loop's arithmetic per event (M2M, G2G, E2E, motion durations in int64 ns; the reasons an
// event has no value) and the summaries over a file, checked against sums done by hand; and the
// split of the command's inputs into full-loop files and the rest.
#include "m2mlat/analysis/full_loop.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::analysis::full_loop_test {
namespace {

using formats::FullLoopRow;

constexpr std::int64_t kT0 = 1'762'872'545'000'000'000;  // ns since 1970, beyond a double's exact range
constexpr std::int64_t kMs = 1'000'000;

// A row from offsets (ns) to kT0, in the rig's column order; nullopt stays missing.
FullLoopRow row(long line, std::optional<std::int64_t> vehicle_on, std::optional<std::int64_t> vehicle_off,
                std::optional<std::int64_t> led_on, std::optional<std::int64_t> station_on,
                std::optional<std::int64_t> station_off, std::optional<std::int64_t> photo) {
  FullLoopRow r;
  r.line = line;
  const std::array<std::optional<std::int64_t>, 6> offsets{vehicle_on, vehicle_off, led_on,
                                                           station_on, station_off, photo};
  for (std::size_t i = 0; i < offsets.size(); ++i)
    if (offsets[i]) r.ns[i] = kT0 + *offsets[i];
  return r;
}

const LoopValue& at(const std::array<LoopValue, 5>& v, LoopQuantity q) {
  return v[static_cast<std::size_t>(q)];
}

TEST(FullLoop, OneEventsChainInIntegerNanoseconds) {
  // Station onset at 0, vehicle onset 48.123457 ms later, LED 77 us after that, photo edge 104.2 ms
  // after the LED: every difference exact to the ns.
  const auto v = loop_values(row(2, 48'123'457, 655'000'001, 48'200'457, 0, 612'000'003, 152'400'458));
  EXPECT_EQ(at(v, LoopQuantity::m2m).ns, 48'123'457);
  EXPECT_EQ(at(v, LoopQuantity::g2g).ns, 104'200'001);
  EXPECT_EQ(at(v, LoopQuantity::e2e).ns, 48'123'457 + 104'200'001);
  EXPECT_EQ(at(v, LoopQuantity::vehicle_motion).ns, 655'000'001 - 48'123'457);
  EXPECT_EQ(at(v, LoopQuantity::station_motion).ns, 612'000'003);
}

TEST(FullLoop, ANegativeM2MIsKeptANegativeG2GIsImpossible) {
  const auto baseline = loop_values(row(2, -300'000, 500 * kMs, 0, 0, 500 * kMs, 100 * kMs));
  EXPECT_EQ(at(baseline, LoopQuantity::m2m).ns, -300'000);
  EXPECT_EQ(at(baseline, LoopQuantity::e2e).ns, 100 * kMs - 300'000);

  const auto photo_first = loop_values(row(2, 50 * kMs, 600 * kMs, 50 * kMs, 0, 600 * kMs, 50 * kMs - 1));
  EXPECT_EQ(at(photo_first, LoopQuantity::g2g), (LoopValue{std::nullopt, LoopExclusion::impossible}));
  EXPECT_EQ(at(photo_first, LoopQuantity::e2e), (LoopValue{std::nullopt, LoopExclusion::impossible}));
  EXPECT_EQ(at(photo_first, LoopQuantity::m2m).ns, 50 * kMs);  // the other quantities keep their values

  // G2G of exactly 0 is possible (an LED and a screen on one board can agree to the ns).
  EXPECT_EQ(at(loop_values(row(2, 1, 2, 5, 0, 3, 5)), LoopQuantity::g2g).ns, 0);
}

TEST(FullLoop, OffBeforeOnMakesOnlyThatSidesDurationImpossible) {
  const auto v =
      loop_values(row(2, 50 * kMs, 30 * kMs, 50 * kMs, 0, -1, 150 * kMs));  // station OFF 1 ns before its ON
  EXPECT_EQ(at(v, LoopQuantity::vehicle_motion).why, LoopExclusion::impossible);
  EXPECT_FALSE(at(v, LoopQuantity::vehicle_motion).ns);
  EXPECT_EQ(at(v, LoopQuantity::station_motion).why, LoopExclusion::impossible);
  EXPECT_EQ(at(v, LoopQuantity::m2m).ns, 50 * kMs);
  EXPECT_EQ(at(v, LoopQuantity::e2e).ns, 150 * kMs);
}

TEST(FullLoop, MissingValuesAndOverflowAreReasonsNotZeros) {
  const auto v = loop_values(row(2, 50 * kMs, std::nullopt, 50 * kMs, std::nullopt, 600 * kMs, 150 * kMs));
  EXPECT_EQ(at(v, LoopQuantity::m2m), (LoopValue{std::nullopt, LoopExclusion::missing}));
  EXPECT_EQ(at(v, LoopQuantity::e2e), (LoopValue{std::nullopt, LoopExclusion::missing}));
  EXPECT_EQ(at(v, LoopQuantity::vehicle_motion).why, LoopExclusion::missing);
  EXPECT_EQ(at(v, LoopQuantity::station_motion).why, LoopExclusion::missing);
  EXPECT_EQ(at(v, LoopQuantity::g2g).ns, 100 * kMs);

  FullLoopRow extreme;
  extreme.ns = {INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN, INT64_MIN, INT64_MAX};
  const auto o = loop_values(extreme);
  EXPECT_EQ(at(o, LoopQuantity::m2m).why, LoopExclusion::overflow);
  EXPECT_EQ(at(o, LoopQuantity::g2g).why, LoopExclusion::overflow);
  EXPECT_EQ(at(o, LoopQuantity::e2e).why, LoopExclusion::overflow);
  EXPECT_EQ(at(o, LoopQuantity::vehicle_motion).ns, 0);

  // M2M and G2G fit, their sum does not.
  FullLoopRow sum;
  sum.ns = {INT64_MAX, INT64_MAX, 0, 0, 0, INT64_MAX};
  EXPECT_EQ(at(loop_values(sum), LoopQuantity::e2e).why, LoopExclusion::overflow);
}

TEST(FullLoop, AFileIsSummarisedPerQuantityWithTheExclusionsCounted) {
  formats::FullLoopImport file;
  // M2M 40, 50, 60 ms; G2G 100, 110, 120 ms; one event without a station onset, one photo before its LED.
  file.rows = {row(2, 40 * kMs, 600 * kMs, 40 * kMs, 0, 500 * kMs, 140 * kMs),
               row(3, 50 * kMs, 700 * kMs, 50 * kMs, 0, 600 * kMs, 160 * kMs),
               row(4, 60 * kMs, 800 * kMs, 60 * kMs, 0, 700 * kMs, 180 * kMs),
               row(5, 55 * kMs, 900 * kMs, 55 * kMs, std::nullopt, 800 * kMs, 155 * kMs),
               row(7, 45 * kMs, 550 * kMs, 45 * kMs, 0, 650 * kMs, 44 * kMs)};
  stats::SummaryOptions options;
  options.thresholds = {core::Duration{150 * kMs}};
  const auto r = analyse_full_loop("run", "run.csv", file, options);
  EXPECT_EQ(r.events, 5u);
  const auto* m2m = r.find(LoopQuantity::m2m);
  ASSERT_NE(m2m, nullptr);
  EXPECT_EQ(m2m->ns, (std::vector<std::int64_t>{40 * kMs, 50 * kMs, 60 * kMs, 45 * kMs}));
  EXPECT_EQ(m2m->lines, (std::vector<std::int64_t>{2, 3, 4, 7}));
  EXPECT_EQ(m2m->excluded, (std::array<std::size_t, 3>{1, 0, 0}));
  EXPECT_DOUBLE_EQ(m2m->summary.mean_ms, 48.75);
  EXPECT_DOUBLE_EQ(m2m->summary.median_ms, 47.5);

  const auto* g2g = r.find(LoopQuantity::g2g);
  EXPECT_EQ(g2g->ns, (std::vector<std::int64_t>{100 * kMs, 110 * kMs, 120 * kMs, 100 * kMs}));
  EXPECT_EQ(g2g->excluded, (std::array<std::size_t, 3>{0, 1, 0}));

  const auto* e2e = r.find(LoopQuantity::e2e);
  EXPECT_EQ(e2e->ns, (std::vector<std::int64_t>{140 * kMs, 160 * kMs, 180 * kMs}));
  EXPECT_EQ(e2e->excluded, (std::array<std::size_t, 3>{1, 1, 0}));
  EXPECT_EQ(e2e->excluded_total(), 2u);
  EXPECT_DOUBLE_EQ(e2e->summary.mean_ms, 160.0);
  EXPECT_DOUBLE_EQ(e2e->summary.sd_ms, 20.0);
  EXPECT_DOUBLE_EQ(e2e->summary.iqr_ms, 20.0);
  ASSERT_EQ(e2e->summary.thresholds.size(), 1u);
  EXPECT_EQ(e2e->summary.thresholds[0].count_above, 2u);  // 160 and 180 ms; strictly above
  EXPECT_EQ(e2e->summary.max->id, 4);                     // the line of the largest

  EXPECT_EQ(r.find(LoopQuantity::vehicle_motion)->summary.n, 5u);
  EXPECT_EQ(r.find(LoopQuantity::station_motion)->summary.n, 4u);
}

TEST(FullLoop, TheCameraFileGivesG2GAlone) {
  formats::CameraLatencyImport file{{45 * kMs, 47 * kMs, -1 * kMs, 52 * kMs}, {2, 3, 4, 6}};
  const auto r = analyse_camera_latency("camera", "camera.txt", file, {});
  EXPECT_EQ(r.format, formats::Format::camera_latency);
  EXPECT_EQ(r.events, 4u);
  EXPECT_EQ(r.find(LoopQuantity::m2m), nullptr);
  EXPECT_EQ(r.find(LoopQuantity::e2e), nullptr);
  const auto* g2g = r.find(LoopQuantity::g2g);
  ASSERT_NE(g2g, nullptr);
  EXPECT_EQ(g2g->summary.n, 3u);
  EXPECT_EQ(g2g->excluded, (std::array<std::size_t, 3>{0, 1, 0}));
  EXPECT_DOUBLE_EQ(g2g->summary.median_ms, 47.0);
  EXPECT_EQ(g2g->summary.min->id, 2);
}

class TakeFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("m2mlat-full-loop-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const auto path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(TakeFiles, FullLoopFilesAreTakenOutTheRestStaysInOrder) {
  const auto loop = write("loop.csv",
                          "VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR\n"
                          "50,600,60,0,500,160\n");
  const auto camera = write("camera.txt", "LATENCY (ms)\n45.5\n");
  const auto events = write("events.log", "GPIO_16_IRQ:1000\n");
  std::vector<std::string> inputs{events, loop, "missing.db", camera};
  const auto results = take_full_loop_files(inputs, std::nullopt, {});
  EXPECT_EQ(inputs, (std::vector<std::string>{events, "missing.db"}));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].scenario, "loop");
  EXPECT_EQ(results[0].find(LoopQuantity::e2e)->ns, (std::vector<std::int64_t>{150}));
  EXPECT_EQ(results[1].scenario, "camera");
  EXPECT_EQ(results[1].find(LoopQuantity::g2g)->ns, (std::vector<std::int64_t>{45'500'000}));

  // --format of another kind takes nothing; a full-loop one takes everything (and names a bad file).
  std::vector<std::string> other{loop};
  EXPECT_TRUE(take_full_loop_files(other, formats::Format::kernel_log, {}).empty());
  EXPECT_EQ(other.size(), 1u);
  std::vector<std::string> forced{events};
  EXPECT_THROW(take_full_loop_files(forced, formats::Format::full_loop_csv, {}), core::Error);
}

TEST_F(TakeFiles, ABadFullLoopFileIsNamedWithItsLine) {
  const auto bad = write("bad.csv",
                         "VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR\n"
                         "50,600,60,0,500,160\n50,600,sixty,0,500,160\n");
  std::vector<std::string> inputs{bad};
  try {
    take_full_loop_files(inputs, std::nullopt, {});
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("bad.csv:3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("field LED_ON"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::analysis::full_loop_test
