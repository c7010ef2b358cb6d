// Per-sample uncertainty: the neighbour rules on hand-made clock tracks, the flags and the gate, and
// the simulator as oracle: over many seeds the intervals hold the true latency as often as they claim.
#include "m2mlat/analysis/uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "m2mlat/analysis/board_record.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/sim/presets.hpp"

namespace m2mlat::analysis {
namespace {

constexpr std::int64_t kT0 = 1'780'304'400'000'000'000;
constexpr std::int64_t kS = 1'000'000'000;

store::ClockSample sample(std::int64_t t_ns, std::int64_t max_ns, std::int64_t est_ns, bool synced = true,
                          std::string source = "chrony") {
  store::ClockSample s;
  s.time = core::TimePoint::from_ns(core::Clock::realtime, t_ns);
  s.source = std::move(source);
  s.max_error_ns = max_ns;
  s.est_error_ns = est_ns;
  s.offset_ns = max_ns / 10;
  s.synchronised = synced;
  return s;
}

TEST(Uncertainty, WorseNeighbourGrownByItsDistance) {
  const auto track =
      make_clock_track({sample(kT0 + 10 * kS, 300'000, 100'000), sample(kT0, 200'000, 50'000)});
  // 4 s after the first sample (grows 60 us at 15 ppm) and 6 s before the second (90 us).
  const auto b = bound_at(track, kT0 + 4 * kS, 15);
  ASSERT_TRUE(b.found);
  EXPECT_TRUE(b.synchronised);
  EXPECT_EQ(b.max_error_ns, std::max(200'000 + 60'000, 300'000 + 90'000));
  EXPECT_EQ(b.est_error_ns, std::max(50'000 + 60'000, 100'000 + 90'000));
  // Before the first sample and after the last: the one neighbour, grown.
  EXPECT_EQ(bound_at(track, kT0 - kS, 15).max_error_ns, 200'000 + 15'000);
  EXPECT_EQ(bound_at(track, kT0 + 12 * kS, 15).max_error_ns, 300'000 + 30'000);
  // Exactly at a sample: that sample and the next one.
  EXPECT_EQ(bound_at(track, kT0, 0).max_error_ns, 300'000);
  EXPECT_FALSE(bound_at(ClockTrack{}, kT0, 15).found);
  EXPECT_EQ(offset_at(track, kT0 + 4 * kS), 20'000);
  EXPECT_EQ(offset_at(track, kT0 + 6 * kS), 30'000);
}

TEST(Uncertainty, TheKernelsStateCountsOnlyWithoutADaemonsOwn) {
  // The reference board of a co-referenced rig: chronyd serves its own clock and reports itself
  // synchronised, while the kernel's adjtimex state still says unsynchronised.
  const auto reference = make_clock_track({sample(kT0, kUnbounded, kUnbounded, false, "adjtimex"),
                                           sample(kT0 + kS, 500'000, 100'000, true, "chrony"),
                                           sample(kT0 + 2 * kS, kUnbounded, kUnbounded, false, "adjtimex")});
  const auto b = bound_at(reference, kT0 + kS, 0);
  ASSERT_TRUE(b.found);
  EXPECT_TRUE(b.synchronised);
  EXPECT_EQ(b.max_error_ns, 500'000);
  // A board with only the kernel's state: that is what it has, and it is used.
  const auto kernel_only = make_clock_track({sample(kT0, 800'000, 200'000, true, "adjtimex")});
  EXPECT_EQ(bound_at(kernel_only, kT0, 0).max_error_ns, 800'000);
  const auto unsynced_kernel = make_clock_track({sample(kT0, kUnbounded, kUnbounded, false, "adjtimex")});
  EXPECT_FALSE(bound_at(unsynced_kernel, kT0, 0).synchronised);
}

TEST(Uncertainty, SumOfBoundsAndRootSumSquareOfEstimates) {
  const auto cause = make_clock_track({sample(kT0, 1'000'000, 300'000)});
  const auto effect = make_clock_track({sample(kT0, 2'000'000, 400'000)});
  UncertaintyOptions o;
  o.growth_ppm = 0;
  o.kernel_max = core::Duration{5'000};
  o.kernel_est = core::Duration{0};
  o.calibration_max = core::Duration{10'000'000};
  o.calibration_est = core::Duration{1'200'000};
  const auto u = pair_uncertainty(cause, effect, kT0 + kS, kT0 + 2 * kS, o);
  EXPECT_EQ(u.flags, 0u);
  EXPECT_EQ(u.sync_max_ns, 3'000'000);
  EXPECT_EQ(u.max_error_ns, 3'000'000 + 5'000 + 10'000'000);
  EXPECT_EQ(u.est_error_ns, 1'300'000);  // sqrt(0.3^2 + 0.4^2 + 1.2^2) ms
}

TEST(Uncertainty, FlagsAndGate) {
  const auto good = make_clock_track({sample(kT0, 1'000'000, 300'000)});
  auto stepped =
      make_clock_track({sample(kT0, 1'000'000, 300'000), sample(kT0 + 2 * kS, 0, 0, true, "step")});
  const auto unsynced = make_clock_track({sample(kT0, kUnbounded, kUnbounded, false)});
  UncertaintyOptions o;
  EXPECT_EQ(pair_uncertainty(good, ClockTrack{}, kT0, kT0 + kS, o).flags, kUncertaintyNoClock);
  const auto u = pair_uncertainty(good, unsynced, kT0, kT0 + kS, o);
  EXPECT_EQ(u.flags, kUncertaintyUnsynchronised);
  EXPECT_EQ(u.max_error_ns, kUnbounded);
  EXPECT_FALSE(u.bounded());
  EXPECT_EQ(pair_uncertainty(good, stepped, kT0 + kS, kT0 + 3 * kS, o).flags, kUncertaintyClockStep);
  EXPECT_EQ(pair_uncertainty(good, stepped, kT0 + 3 * kS, kT0 + 4 * kS, o).flags, 0u);
  // The gate looks at the clock part only.
  o.sync_gate = core::Duration{1'500'000};
  o.kernel_max = core::Duration{10'000'000};
  o.growth_ppm = 0;
  EXPECT_EQ(pair_uncertainty(good, good, kT0, kT0 + kS, o).flags, kUncertaintyGated);
  o.sync_gate = core::Duration{2'000'000};
  EXPECT_EQ(pair_uncertainty(good, good, kT0, kT0 + kS, o).flags, 0u);
  EXPECT_TRUE(pair_uncertainty(good, unsynced, kT0, kT0 + kS, o).gated());

  const std::vector<SampleUncertainty> all{pair_uncertainty(good, good, kT0, kT0 + kS, o),
                                           pair_uncertainty(good, unsynced, kT0, kT0 + kS, o),
                                           pair_uncertainty(good, ClockTrack{}, kT0, kT0 + kS, o)};
  const auto s = summarize_uncertainty(all, true);
  EXPECT_EQ(s.samples, 3u);
  EXPECT_EQ(s.known, 2u);
  EXPECT_EQ(s.bounded, 1u);
  EXPECT_EQ(s.flagged, 1u);
  EXPECT_EQ(s.refused, 1u);
  EXPECT_DOUBLE_EQ(s.median_max_ms, 12.0);
  EXPECT_NEAR(s.share_flagged(), 1.0 / 3, 1e-12);
}

TEST(Uncertainty, GateRefuseLeavesSamplesOutOfTheStatistics) {
  ScenarioResult r;
  r.input.cause.seq = {0, 1, 2};
  r.input.effect.seq = {0, 1, 2};
  for (std::int64_t i = 0; i < 3; ++i) {
    pairing::Pair p;
    p.cause_index = p.effect_index = i;
    p.cause_time = core::TimePoint::from_ns(core::Clock::realtime, kT0 + i * 10 * kS);
    p.effect_time = p.cause_time + core::Duration{(i + 1) * 100'000'000};
    r.match.pairs.push_back(p);
  }
  // The effect board loses synchronisation between the second and the third pair.
  const auto cause = make_clock_track({sample(kT0, 1'000'000, 300'000)});
  const auto effect =
      make_clock_track({sample(kT0, 1'000'000, 300'000), sample(kT0 + 15 * kS, 1'000'000, 300'000),
                        sample(kT0 + 21 * kS, kUnbounded, kUnbounded, false)});
  UncertaintyOptions o;
  o.sync_gate = core::Duration{5'000'000};
  summarize(r, {});
  EXPECT_EQ(r.summary.n, 3u);
  attach_uncertainty(r, cause, effect, o, {});
  ASSERT_EQ(r.uncertainty.size(), 3u);
  EXPECT_TRUE(r.uncertainty[2].gated());
  EXPECT_FALSE(r.uncertainty[0].gated());
  EXPECT_FALSE(r.uncertainty[1].gated());
  EXPECT_EQ(r.summary.n, 3u);  // flagged only
  o.gate_refuse = true;
  attach_uncertainty(r, cause, effect, o, {});
  EXPECT_EQ(r.summary.n, 2u);
  EXPECT_DOUBLE_EQ(r.summary.max->ms(), 200.0);
}

// The simulator knows every event's true time, so it can check the intervals.
struct Coverage {
  std::size_t samples = 0, within_max = 0, within_est = 0, within_2est = 0;
};

Coverage run_seed(std::uint64_t seed, const std::string& preset, const std::string& path) {
  auto config = sim::preset(preset);
  config.seed = seed;
  config.manoeuvres = 25;
  std::vector<sim::TruePair> truth;
  {
    auto store = store::Store::open(path);
    capture::record_simulation(store, config, "coverage", [&](const sim::Chunk& chunk, std::int64_t) {
      truth.insert(truth.end(), chunk.pairs.begin(), chunk.pairs.end());
    });
  }
  store::Options read;
  read.read_only = true;
  const auto store = store::Store::open(path, read);
  auto result = analyse(load_scenario(store, config.scenario, {}), {}, {});
  UncertaintyOptions o;
  // Each board's interrupt latency lies in [min, max] of its sensor model: their difference is bounded
  // by the larger max, and its sd (exponential, mean 3 us) is about 4 us.
  o.kernel_max = std::max(config.cause_sensor.irq_latency.max, config.effect_sensor.irq_latency.max);
  o.kernel_est = core::Duration{4'300};
  attach_board_record(result, store, o, {});
  EXPECT_EQ(result.uncertainty.size(), result.match.pairs.size());
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> true_latency;
  for (const auto& t : truth) true_latency[{t.cause_index, t.effect_index}] = t.true_latency.count();
  Coverage c;
  for (std::size_t i = 0; i < result.match.pairs.size(); ++i) {
    const auto& p = result.match.pairs[i];
    const auto it = true_latency.find({p.cause_index, p.effect_index});
    if (it == true_latency.end()) continue;  // a wrong pair: not a clock question
    const auto& u = result.uncertainty[i];
    EXPECT_TRUE(u.bounded());
    const std::int64_t error = std::abs(p.latency().count() - it->second);
    ++c.samples;
    c.within_max += error <= u.max_error_ns;
    c.within_est += error <= u.est_error_ns;
    c.within_2est += error <= 2 * u.est_error_ns;
  }
  return c;
}

TEST(Uncertainty, SimulatorIntervalsHoldTheTrueLatency) {
  const auto path =
      (std::filesystem::temp_directory_path() /
       ("m2mlat-uncertainty-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".db"))
          .string();
  for (const std::string preset : {"static_wifi", "dynamic_autonomous"}) {
    Coverage total;
    for (std::uint64_t seed = 1; seed <= 50; ++seed) {
      for (const char* s : {"", "-wal", "-shm"}) std::filesystem::remove(path + s);
      const auto c = run_seed(seed * 7919, preset, path);
      total.samples += c.samples;
      total.within_max += c.within_max;
      total.within_est += c.within_est;
      total.within_2est += c.within_2est;
    }
    for (const char* s : {"", "-wal", "-shm"}) std::filesystem::remove(path + s);
    const auto share = [&](std::size_t k) {
      return static_cast<double>(k) / static_cast<double>(total.samples);
    };
    std::printf("%s: %zu samples, within max %.4f, within est %.4f, within 2 est %.4f\n", preset.c_str(),
                total.samples, share(total.within_max), share(total.within_est), share(total.within_2est));
    ASSERT_GT(total.samples, 1000u);
    EXPECT_EQ(total.within_max, total.samples) << preset;  // the bound always holds
    EXPECT_GE(share(total.within_est), 0.68) << preset;    // est_error as 1 sigma
    EXPECT_GE(share(total.within_2est), 0.95) << preset;   // 2 sigma
  }
}

}  // namespace
}  // namespace m2mlat::analysis
