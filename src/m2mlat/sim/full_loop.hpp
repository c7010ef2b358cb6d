// The simulated full loop: the twin of a rig that measures motion-to-motion (M2M), glass-to-glass
// (G2G) and end-to-end (E2E = M2M + G2G) latency with two gyroscopes, an LED and a phototransistor.
//
// Per manoeuvre: the operator's hand turns the station's wheel (sim/gyro_motion.hpp: minimum jerk,
// peak rate drawn from slow to fast), the vehicle's actuator repeats it after the M2M delay, and the
// station's and the vehicle's gyroscopes are read (sim/gyro.hpp). The vehicle board switches an LED
// in its camera's view once it has seen its wheel move (the trigger delay after the true onset), and
// stamps the write with the time before and after it. The camera -> encoder -> network -> decoder ->
// screen path carries the light to the operator's screen, where a phototransistor fires an edge:
//   the first frame whose exposure saw the LED lit for at least half of it (frame phase and period,
//   exposure), the frame's readout and encoding, the network, decoding, the next refresh of the screen
//   (refresh phase and period) and the scan to the phototransistor's row, the panel's pixel response,
//   the phototransistor's rise to the comparator's threshold, and the station's interrupt latency.
// True G2G = photo edge - LED lit; true M2M = vehicle onset - station onset.
//
// Each board has its own clock: its stamps are the true time plus the board's offset (drawn within
// +-sync_max_ns, constant over the run); the analysis is told that bound, as a daemon's clock samples
// would tell it. "baseline": both gyroscopes on one rigid
// body (the vehicle chip sees the hand: true M2M = 0). "single_board": no gyroscopes; the LED is
// switched on a schedule and the phototransistor is on the same board (a camera pointed at a
// monitor): G2G alone, no clock sync involved.
//
// All times are int64 ns on Clock::simulated; deterministic per seed.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/sim/gyro.hpp"
#include "m2mlat/sim/gyro_motion.hpp"

namespace m2mlat::sim {

struct FullLoopConfig {
  std::uint64_t seed = 1;
  int manoeuvres = 40;
  bool baseline = false;      // both chips on one body: true M2M = 0
  bool single_board = false;  // LED on a schedule, photo on the same board; no gyroscopes
  GyroConfig gyro;
  ActuatorLimits actuator;
  double peak_min_deg_s = 20, peak_max_deg_s = 400;  // the hand's peak rate, uniform, deg/s
  std::int64_t motion_min_ns = 400'000'000, motion_max_ns = 1'200'000'000;  // hand motion duration, ns
  // Rest between manoeuvres, ns: longer than the reference detector's re-arming (10,000 still samples,
  // 1.25 s at 8 kHz), so that both detectors see every motion.
  std::int64_t gap_min_ns = 1'500'000'000, gap_max_ns = 2'500'000'000;
  std::int64_t m2m_min_ns = 60'000'000, m2m_max_ns = 160'000'000;  // true M2M delay, uniform, ns
  // The vehicle board: from the true onset to the LED write (its online detector), uniform, ns.
  std::int64_t trigger_min_ns = 2'000'000, trigger_max_ns = 8'000'000;
  std::int64_t led_write_ns = 4'000;  // the GPIO write between the stamps before and after it, ns
  // Camera: frame period (30 fps), exposure; readout + encoding (uniform); network (base + exponential
  // with this mean); decoding (uniform); screen refresh (60 Hz) and the phototransistor's row (share of
  // the scan); the panel's pixel response (uniform); the phototransistor's rise to threshold.
  std::int64_t frame_ns = 33'333'333, exposure_ns = 10'000'000;
  std::int64_t encode_min_ns = 8'000'000, encode_max_ns = 14'000'000;
  std::int64_t network_ns = 20'000'000, network_jitter_ns = 5'000'000;
  std::int64_t decode_min_ns = 3'000'000, decode_max_ns = 6'000'000;
  std::int64_t refresh_ns = 16'666'667;
  double photo_row = 0.5;
  std::int64_t pixel_min_ns = 2'000'000, pixel_max_ns = 6'000'000;
  std::int64_t photo_rise_ns = 20'000;  // phototransistor + comparator, ns
  std::int64_t irq_mean_ns = 5'000;     // the station's interrupt latency (exponential mean), ns
  std::int64_t sync_max_ns = 200'000;   // each board's clock offset lies within +-this, ns
};

// Throws core::Error(usage) naming the field out of range.
void check(const FullLoopConfig& config);

// One manoeuvre's truth and its stamps. True times on the simulator's time base; stamps on the
// board's clock (true + that board's offset).
struct FullLoopManoeuvre {
  RateMotion station, vehicle;      // the true motions (empty durations in single_board)
  std::int64_t led_true_ns = 0;     // the LED lit (the write's end), true time
  std::int64_t led_stamp_ns = 0;    // the vehicle board's stamp: middle of [before, after]
  std::int64_t led_bound_ns = 0;    // half-width of [before, after], ns
  std::int64_t photo_true_ns = 0;   // the phototransistor's output crossing, true time
  std::int64_t photo_stamp_ns = 0;  // the station board's interrupt stamp
  std::int64_t true_m2m_ns() const { return vehicle.onset_ns - station.onset_ns; }
  std::int64_t true_g2g_ns() const { return photo_true_ns - led_true_ns; }
  std::int64_t true_e2e_ns() const { return true_m2m_ns() + true_g2g_ns(); }
};

struct FullLoopRun {
  FullLoopConfig config;
  std::vector<FullLoopManoeuvre> manoeuvres;
  core::RateTrace station_trace, vehicle_trace;  // stamps on each board's clock; empty in single_board
  std::int64_t station_offset_ns = 0, vehicle_offset_ns = 0;  // board clock - true time, ns
  std::int64_t end_ns = 0;  // true end of the run (the traces stop here), ns
};

FullLoopRun simulate_full_loop(const FullLoopConfig& config);

// What one board's clock daemon reports over the run: a sample a second from true time 0 to one
// second past the end, on the board's clock, each bounding its offset by sync_max_ns (est_error =
// sync_max / sqrt 3, the standard uncertainty of a uniform offset within the bound).
struct FullLoopClockSample {
  std::int64_t time_ns = 0;       // on the board's clock, ns
  std::int64_t max_error_ns = 0;  // ns
  std::int64_t est_error_ns = 0;  // ns
};
std::vector<FullLoopClockSample> board_clock_samples(const FullLoopRun& run, bool station);

// The demo's full-loop scenarios: "full_loop" (the defaults), "full_loop_baseline" (baseline) and
// "full_loop_single_board" (single_board); nullopt for any other name.
std::optional<FullLoopConfig> full_loop_preset(std::string_view name);

}  // namespace m2mlat::sim
