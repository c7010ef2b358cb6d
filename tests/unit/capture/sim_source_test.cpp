// The simulated source: one side of the rig, renamed, unchanged otherwise, and recorded end to end.
#include "m2mlat/capture/sim_source.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::capture {
namespace {

sim::RigConfig small_run() {
  auto config = sim::preset("static_wifi");
  config.manoeuvres = 20;
  return config;
}

TEST(SimSource, HandsOverOneSidesEventsUnchangedButForTheNames) {
  const auto truth = sim::simulate(small_run());
  SimSource source({"truck", "steer", core::Role::effect, small_run(), false});
  ReadResult out;
  while (!out.finished) source.read(out, 7);
  ASSERT_EQ(out.events.size(), truth.effect_events.size());
  for (std::size_t i = 0; i < out.events.size(); ++i) {
    auto expected = truth.effect_events[i];
    expected.node = "truck";
    expected.channel = "steer";
    EXPECT_EQ(out.events[i], expected);
  }
  // The effect board's daemon readings come along, each as the store keeps it, in time order; its
  // daemon follows the operator board's clock (co-referenced).
  std::vector<store::ClockSample> expected_samples;
  ASSERT_EQ(sim_reference(small_run(), core::Role::effect), small_run().cause_node);
  for (const auto& s : truth.clock_samples)
    if (s.node == core::Role::effect)
      expected_samples.push_back(sim_clock_sample(s, 0, small_run().cause_node));
  ASSERT_FALSE(expected_samples.empty());
  EXPECT_NE(expected_samples.front().detail_json.find("\"ref_name\":\"operator\""), std::string::npos);
  EXPECT_EQ(expected_samples.front().detail_json.find("true_error"), std::string::npos);
  EXPECT_EQ(out.clock_samples, expected_samples);
}

TEST(SimSource, RecordsARunIntoAStoreUntilItEnds) {
  const auto path =
      (std::filesystem::temp_directory_path() / ("m2mlat-simsrc-" + std::to_string(::getpid()) + ".db"))
          .string();
  std::filesystem::remove(path);
  {
    auto store = store::Store::open(path);
    SimSource source({"operator", "wheel", core::Role::cause, small_run(), false});
    RecorderOptions options;
    options.session.node = "operator";
    options.session.role = core::Role::cause;
    Recorder recorder(store, source, options);
    const auto counters = recorder.run(-1);
    EXPECT_EQ(counters.stop_reason, "source finished");
    const auto truth = sim::simulate(small_run());
    EXPECT_EQ(counters.events, truth.cause_events.size());
    EXPECT_EQ(store.event_count(counters.session_id), static_cast<std::int64_t>(truth.cause_events.size()));
    // The operator board's simulated clock state is stored beside its events, in its session.
    std::size_t cause_samples = 0;
    for (const auto& s : truth.clock_samples) cause_samples += s.node == core::Role::cause ? 1 : 0;
    const auto stored = store.clock_samples(counters.session_id);
    EXPECT_EQ(stored.size(), cause_samples);
    for (const auto& s : stored) EXPECT_EQ(s.source, "sim");
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}

}  // namespace
}  // namespace m2mlat::capture
