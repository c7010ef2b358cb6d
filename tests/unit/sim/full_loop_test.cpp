// The simulated full loop: deterministic, and its truth as its settings say.
#include "m2mlat/sim/full_loop.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::sim::full_loop_test {

namespace {

FullLoopConfig small(std::uint64_t seed) {
  FullLoopConfig c;
  c.seed = seed;
  c.manoeuvres = 6;
  return c;
}

TEST(FullLoop, SameSeedSameRunOtherSeedOtherRun) {
  const auto a = simulate_full_loop(small(3)), b = simulate_full_loop(small(3)),
             d = simulate_full_loop(small(4));
  ASSERT_EQ(a.manoeuvres.size(), 6u);
  for (std::size_t k = 0; k < a.manoeuvres.size(); ++k) {
    EXPECT_EQ(a.manoeuvres[k].photo_stamp_ns, b.manoeuvres[k].photo_stamp_ns);
    EXPECT_EQ(a.manoeuvres[k].station.onset_ns, b.manoeuvres[k].station.onset_ns);
  }
  ASSERT_EQ(a.vehicle_trace.samples.size(), b.vehicle_trace.samples.size());
  EXPECT_EQ(a.vehicle_trace.samples.back().raw, b.vehicle_trace.samples.back().raw);
  EXPECT_NE(a.manoeuvres[0].photo_true_ns, d.manoeuvres[0].photo_true_ns);
}

TEST(FullLoop, TruthFollowsTheSettings) {
  const auto c = small(7);
  const auto run = simulate_full_loop(c);
  // The shortest and the longest path from the LED to the phototransistor the settings allow (the
  // network's exponential tail aside).
  const std::int64_t shortest = c.exposure_ns / 2 + c.encode_min_ns + c.network_ns + c.decode_min_ns +
                                static_cast<std::int64_t>(c.photo_row * static_cast<double>(c.refresh_ns)) +
                                c.pixel_min_ns + c.photo_rise_ns;
  std::int64_t previous_end = 0;
  for (const auto& m : run.manoeuvres) {
    EXPECT_GE(m.true_m2m_ns(), c.m2m_min_ns);
    EXPECT_LE(m.true_m2m_ns(), c.m2m_max_ns);
    EXPECT_GE(m.true_g2g_ns(), shortest);
    EXPECT_LE(m.true_g2g_ns() - c.network_jitter_ns * 20,
              shortest + c.frame_ns + c.refresh_ns + (c.encode_max_ns - c.encode_min_ns) +
                  (c.decode_max_ns - c.decode_min_ns) + (c.pixel_max_ns - c.pixel_min_ns));
    EXPECT_EQ(m.true_e2e_ns(), m.true_m2m_ns() + m.true_g2g_ns());
    // The LED: lit after the trigger delay, its stamp (less the board's offset) within its bound.
    EXPECT_GE(m.led_true_ns - m.vehicle.onset_ns, c.trigger_min_ns);
    EXPECT_LE(m.led_true_ns - m.vehicle.onset_ns, c.trigger_max_ns + c.led_write_ns);
    EXPECT_LE(std::llabs(m.led_stamp_ns - run.vehicle_offset_ns - m.led_true_ns), m.led_bound_ns);
    // The photo edge is stamped on the station board, after the edge (its interrupt latency).
    EXPECT_GE(m.photo_stamp_ns - run.station_offset_ns, m.photo_true_ns);
    EXPECT_GT(m.station.onset_ns, previous_end);  // one manoeuvre at a time
    previous_end = std::max(m.vehicle.end_ns(), m.photo_true_ns);
  }
  EXPECT_LE(std::llabs(run.station_offset_ns), c.sync_max_ns);
  EXPECT_LE(std::llabs(run.vehicle_offset_ns), c.sync_max_ns);
  // The traces are on each board's clock and span the run.
  ASSERT_FALSE(run.station_trace.samples.empty());
  EXPECT_LT(run.station_trace.samples.front().time_ns - run.station_offset_ns, 1'000'000);
  EXPECT_GT(run.vehicle_trace.samples.back().time_ns - run.vehicle_offset_ns, run.end_ns - 1'000'000);
}

TEST(FullLoop, BaselineHasZeroM2mAndSingleBoardHasNoGyroscopes) {
  auto c = small(9);
  c.baseline = true;
  for (const auto& m : simulate_full_loop(c).manoeuvres) EXPECT_EQ(m.true_m2m_ns(), 0);
  c.baseline = false;
  c.single_board = true;
  const auto run = simulate_full_loop(c);
  EXPECT_TRUE(run.station_trace.samples.empty());
  EXPECT_TRUE(run.vehicle_trace.samples.empty());
  EXPECT_EQ(run.station_offset_ns, run.vehicle_offset_ns);  // one board, one clock
  for (const auto& m : run.manoeuvres) EXPECT_GT(m.true_g2g_ns(), 0);
}

TEST(FullLoop, BadSettingNamed) {
  auto c = small(1);
  c.exposure_ns = c.frame_ns + 1;
  try {
    simulate_full_loop(c);
    FAIL() << "accepted an exposure longer than the frame";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("exposure_ns"), std::string::npos);
  }
}

}  // namespace

}  // namespace m2mlat::sim::full_loop_test
