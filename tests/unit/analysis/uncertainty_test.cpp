// Per-sample uncertainty: the neighbour rules on hand-made clock tracks, the two clock rules
// (independent, co-referenced), the flags and the gate, and the simulator as oracle: over 40 seeds of
// the four presets the intervals hold the true latency as often as they claim.
#include "m2mlat/analysis/uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "m2mlat/analysis/board_record.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/truth_check.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/stats/quantile.hpp"

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
  // u: each neighbour's estimate and a drift of 15 / sqrt(3) ppm over its distance, in quadrature:
  // sqrt(50^2 + 34.64^2) = 60.83 us and sqrt(100^2 + 51.96^2) = 112.69 us; the worse.
  EXPECT_EQ(b.u_ns, 112'694);
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

TEST(Uncertainty, SumOfBoundsAndRootSumSquareOfStandardUncertainties) {
  const auto cause = make_clock_track({sample(kT0, 1'000'000, 300'000)});
  const auto effect = make_clock_track({sample(kT0, 2'000'000, 400'000)});
  UncertaintyOptions o;
  o.growth_ppm = 0;
  o.kernel_max = core::Duration{5'000};
  o.kernel_u = core::Duration{0};
  o.path_u = core::Duration{0};
  o.calibration_max = core::Duration{10'000'000};
  o.calibration_u = core::Duration{1'200'000};
  const auto u = pair_uncertainty(cause, effect, kT0 + kS, kT0 + 2 * kS, o);
  EXPECT_EQ(u.flags, 0u);
  EXPECT_EQ(u.sync_max_ns, 3'000'000);
  EXPECT_EQ(u.max_error_ns, 3'000'000 + 5'000 + 10'000'000);
  EXPECT_EQ(u.u_ns, 1'300'000);  // sqrt(0.3^2 + 0.4^2 + 1.2^2) ms
  EXPECT_EQ(u.expanded_ns(), 2'600'000);
  // The defaults add each board's interrupt timestamp (5 us) and each path's asymmetry (100 us):
  // sqrt(0.3^2 + 0.4^2 + 1.2^2 + 2 x 0.1^2 + 2 x 0.005^2) ms = 1.307689 ms. The bound is unchanged.
  const UncertaintyOptions defaults;
  EXPECT_EQ(defaults.kernel_u.count(), 5'000);
  EXPECT_EQ(defaults.path_u.count(), 100'000);
  o.kernel_u = defaults.kernel_u;
  o.path_u = defaults.path_u;
  const auto d = pair_uncertainty(cause, effect, kT0 + kS, kT0 + 2 * kS, o);
  EXPECT_EQ(d.u_ns, 1'307'689);
  EXPECT_EQ(d.max_error_ns, u.max_error_ns);
  // Edges followed by bounces (pairing::Pair::bounce_span_ns) widen the bound by the span, not u.
  const auto b = pair_uncertainty(cause, effect, kT0 + kS, kT0 + 2 * kS, o, 2'500'000);
  EXPECT_EQ(b.max_error_ns, u.max_error_ns + 2'500'000);
  EXPECT_EQ(b.u_ns, d.u_ns);
}

// A latency whose effect was corrected by a clock step of known size carries the size's uncertainty:
// its bound adds to the worst case, its standard uncertainty to u in quadrature.
TEST(Uncertainty, ACorrectedEventCarriesItsStepsUncertainty) {
  const auto cause = make_clock_track({sample(kT0, 1'000'000, 300'000)});
  const auto effect = make_clock_track({sample(kT0, 2'000'000, 400'000)});
  UncertaintyOptions o;
  o.growth_ppm = 0;
  o.kernel_u = o.path_u = core::Duration{0};
  ScenarioResult result;
  for (std::int64_t k = 0; k < 2; ++k) {
    result.input.cause.t_ns.push_back(kT0 + k * kS);
    result.input.effect.t_ns.push_back(kT0 + k * kS + kS / 2);
    result.match.pairs.push_back({static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(k), 0});
  }
  result.steps.effect.mark = {StepMark::none, StepMark::corrected};
  result.steps.effect.bound_of = {0, 1};
  result.steps.effect.bounds = {{}, {1'200'000, 1'200'000}};
  attach_uncertainty(result, cause, effect, o, {});
  ASSERT_EQ(result.uncertainty.size(), 2u);
  EXPECT_EQ(result.uncertainty[0].max_error_ns, 3'000'000);
  EXPECT_EQ(result.uncertainty[0].u_ns, 500'000);  // sqrt(0.3^2 + 0.4^2) ms
  EXPECT_EQ(result.uncertainty[1].max_error_ns, 3'000'000 + 1'200'000);
  EXPECT_EQ(result.uncertainty[1].u_ns, 1'300'000);  // sqrt(0.5^2 + 1.2^2) ms
}

TEST(Uncertainty, ACoReferencedBoardCountsTheCauseClockOnlyByItsMotion) {
  // The operator's daemon reports a rate uncertainty of 100 ppm; the vehicle's follows the operator.
  auto operator_sample = sample(kT0, 1'000'000, 200'000);
  operator_sample.detail_json = R"({"skew_ppm":100,"ref_name":""})";
  auto vehicle_sample = sample(kT0, 2'000'000, 50'000);
  vehicle_sample.detail_json = R"({"skew_ppm":30,"ref_name":"operator"})";
  auto cause = make_clock_track({operator_sample});
  cause.node = "operator";
  const auto effect = make_clock_track({vehicle_sample});
  ASSERT_EQ(cause.skew_ppm, std::vector<double>{100});
  EXPECT_EQ(effect.reference, "operator");
  UncertaintyOptions o;
  o.growth_ppm = 0;
  // 1 s apart: the operator's clock moves by 100 ppm x 1 s = 100 us; u = sqrt(50^2 + 100^2 (path) +
  // 100^2 (motion) + 2 x 5^2) us.
  EXPECT_EQ(pair_uncertainty(cause, effect, kT0, kT0 + kS, o).u_ns, 150'167);
  // 10 s apart: the motion is capped at two independent readings, sqrt(2) x 200 us.
  EXPECT_EQ(
      pair_uncertainty(cause, effect, kT0, kT0 + 10 * kS, o).u_ns,
      std::llround(std::sqrt(50'000.0 * 50'000 + 2 * 200'000.0 * 200'000 + 100'000.0 * 100'000 + 2 * 25e6)));
  // Independent boards (the vehicle follows another node): both clocks and both paths in full,
  // sqrt(200^2 + 50^2 + 2 x 100^2 + 2 x 5^2) us. The bound is the same either way.
  auto unnamed = cause;
  unnamed.node = "station";
  EXPECT_EQ(pair_uncertainty(unnamed, effect, kT0, kT0 + kS, o).u_ns, 250'100);
  EXPECT_EQ(pair_uncertainty(unnamed, effect, kT0, kT0 + kS, o).max_error_ns,
            pair_uncertainty(cause, effect, kT0, kT0 + kS, o).max_error_ns);
  // A detail that is not JSON, or lacks the members, leaves no rate and no reference.
  auto odd = sample(kT0, 1'000'000, 200'000);
  odd.detail_json = "not json";
  const auto plain = make_clock_track({odd, sample(kT0 + kS, 1'000'000, 200'000)});
  EXPECT_EQ(plain.skew_ppm, (std::vector<double>{0, 0}));
  EXPECT_TRUE(plain.reference.empty());
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
    p.cause_index = p.effect_index = static_cast<std::uint32_t>(i);
    r.input.cause.t_ns.push_back(kT0 + i * 10 * kS);
    r.input.effect.t_ns.push_back(r.input.cause.t_ns.back() + (i + 1) * 100'000'000);
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

TEST(Uncertainty, TruthCheckCountsCoverageOverTheCorrectBoundedPairs) {
  ScenarioResult r;
  std::vector<sim::TruePair> truth;
  // Errors (measured - true) of 100, -300, 50 and 900 us; a fifth pair is wrong, a sixth unbounded.
  const std::int64_t errors_us[] = {100, -300, 50, 900, 0, 10};
  for (std::int64_t i = 0; i < 6; ++i) {
    pairing::Pair p;
    p.cause_index = static_cast<std::uint32_t>(i);
    p.effect_index = static_cast<std::uint32_t>(i == 4 ? 5 : i);  // pair 4 takes the wrong effect
    r.match.pairs.push_back(p);
    truth.push_back(
        {i, i, i, core::Duration{800'000'000 - errors_us[i] * 1000}, core::Duration{800'000'000}});
    SampleUncertainty u;
    u.u_ns = 200'000;  // U95 = 400 us
    u.max_error_ns = i == 5 ? kUnbounded : 1'000'000;
    if (i == 5) u.flags = kUncertaintyUnsynchronised, u.u_ns = kUnbounded;
    r.uncertainty.push_back(u);
  }
  const auto check = check_against_truth(r, truth);
  EXPECT_EQ(check.correct, 5);
  EXPECT_EQ(check.wrong, 1);
  EXPECT_EQ(check.with_uncertainty, 4);  // correct and bounded
  EXPECT_EQ(check.within_u, 2);          // 100, 50 <= 200
  EXPECT_EQ(check.within_U95, 3);        // and 300 <= 400
  EXPECT_EQ(check.within_max, 4);
  EXPECT_DOUBLE_EQ(check.coverage_U95(), 0.75);
  EXPECT_DOUBLE_EQ(check.median_abs_error_ns, 200'000);  // of 50, 100, 300, 900 us
  EXPECT_DOUBLE_EQ(check.median_U95_ns, 400'000);
  EXPECT_DOUBLE_EQ(check.width_ratio(), 2.0);
  EXPECT_EQ(coverage_points(r, truth).size(), 4u);
  // Without an uncertainty (no clock samples) there is nothing to cover.
  r.uncertainty.clear();
  const auto none = check_against_truth(r, truth);
  EXPECT_EQ(none.with_uncertainty, 0);
  EXPECT_TRUE(std::isnan(none.coverage_U95()));
  EXPECT_TRUE(std::isnan(none.width_ratio()));
}

// The simulator knows every event's true time, so it can check the intervals: each run is recorded
// into a store as two boards would record it, read back, paired and given its uncertainty with the
// default options, and its correct pairs compared with the truth (analysis/truth_check.hpp; a wrong
// pair is a pairing question and is left out).
struct Sweep {
  std::vector<CoveragePoint> points;
  std::int64_t wrong = 0;
};

// One run into `store`, under its own scenario name (one store holds a preset's seeds: a file per
// run would spend the time on creating and syncing files).
void run_seed(store::Store& store, std::uint64_t seed, const std::string& preset, Sweep& sweep) {
  auto config = sim::preset(preset);
  config.seed = seed;
  config.scenario = preset + "-" + std::to_string(seed);
  std::vector<sim::TruePair> truth;
  capture::record_simulation(store, config, "coverage", [&](const sim::Chunk& chunk, std::int64_t) {
    truth.insert(truth.end(), chunk.pairs.begin(), chunk.pairs.end());
  });
  auto result = analyse(load_scenario(store, config.scenario, {}), {}, {});
  attach_board_record(result, store, {}, {});
  ASSERT_EQ(result.uncertainty.size(), result.match.pairs.size());
  const auto check = check_against_truth(result, truth);
  ASSERT_EQ(check.with_uncertainty, check.correct) << preset << " seed " << seed;  // every sample bounded
  sweep.wrong += check.wrong;
  const auto points = coverage_points(result, truth);
  sweep.points.insert(sweep.points.end(), points.begin(), points.end());
}

TEST(Uncertainty, SimulatorSweepIsCalibrated) {
  const auto path =
      (std::filesystem::temp_directory_path() /
       ("m2mlat-uncertainty-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".db"))
          .string();
  constexpr std::uint64_t kSeeds = 40;
  for (const std::string preset :
       {"static_wifi", "static_5g", "dynamic_co_referenced", "dynamic_autonomous"}) {
    Sweep sweep;
    for (const char* s : {"", "-wal", "-shm"}) std::filesystem::remove(path + s);
    {
      store::Options scratch;  // a scratch file: no fsync, the same code otherwise
      scratch.durability = store::Durability::off;
      auto store = store::Store::open(path, scratch);
      for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) run_seed(store, seed, preset, sweep);
    }
    const auto n = static_cast<double>(sweep.points.size());
    std::size_t within_u = 0, within_U95 = 0, within_max = 0;
    std::vector<std::int64_t> errors, widths, bounds;
    for (const auto& [error, u] : sweep.points) {
      within_u += error <= u.u_ns;
      within_U95 += error <= u.expanded_ns();
      within_max += error <= u.max_error_ns;
      errors.push_back(error);
      widths.push_back(u.expanded_ns());
      bounds.push_back(u.max_error_ns);
    }
    const double median_error = stats::median(errors), median_width = stats::median(widths);
    std::printf(
        "%s: %zu correct pairs (%lld wrong left out), within u %.3f, within U95 %.3f, within max %.3f, "
        "median |error| %.1f us, median U95 %.1f us (%.2fx), median max_error %.2f ms\n",
        preset.c_str(), sweep.points.size(), static_cast<long long>(sweep.wrong),
        static_cast<double>(within_u) / n, static_cast<double>(within_U95) / n,
        static_cast<double>(within_max) / n, median_error / 1e3, median_width / 1e3,
        median_width / median_error, stats::median(bounds) / 1e6);
    ASSERT_GT(sweep.points.size(), 2000u) << preset;
    EXPECT_EQ(within_max, sweep.points.size()) << preset;            // the worst case always holds
    EXPECT_GE(static_cast<double>(within_U95) / n, 0.93) << preset;  // k = 2: honest, not too narrow
    EXPECT_LE(static_cast<double>(within_U95) / n, 0.97) << preset;  // ... nor too wide
    EXPECT_LE(median_width, 4 * median_error) << preset;
  }
  for (const char* s : {"", "-wal", "-shm"}) std::filesystem::remove(path + s);
}

}  // namespace
}  // namespace m2mlat::analysis
