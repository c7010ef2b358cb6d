// The simulated full loop (see full_loop.hpp).
#include "m2mlat/sim/full_loop.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/sim/random.hpp"

namespace m2mlat::sim {

namespace {

// Stream numbers: fixed forever, or every seed's runs change.
constexpr std::uint64_t kLoopStreams = 0x666c'0000;  // "fl"
enum : std::uint64_t { kPlan = 0, kClocks = 1, kPath = 2 };
constexpr std::uint64_t kStationChip = 0x666c'0100, kVehicleChip = 0x666c'0101;
constexpr std::int64_t kStart = 500'000'000;  // rest before the first manoeuvre, ns

// The first instant of period `period` and phase `phase` at or after t.
std::int64_t next_tick(std::int64_t t, std::int64_t phase, std::int64_t period) {
  if (t <= phase) return phase;
  return phase + (t - phase + period - 1) / period * period;
}

// When the phototransistor on the screen fires for an LED lit at `lit` (true time, ns).
std::int64_t photo_edge(const FullLoopConfig& c, std::int64_t lit, std::int64_t frame_phase,
                        std::int64_t refresh_phase, Rng& path) {
  // The first frame whose exposure [start, start + exposure] saw the LED lit for at least half of it.
  const std::int64_t start = next_tick(lit - c.exposure_ns / 2, frame_phase, c.frame_ns);
  std::int64_t t = start + c.exposure_ns;  // the frame is read out once exposed
  t += path.uniform_int(c.encode_min_ns, c.encode_max_ns);
  t +=
      c.network_ns + static_cast<std::int64_t>(static_cast<double>(c.network_jitter_ns) * path.exponential());
  t += path.uniform_int(c.decode_min_ns, c.decode_max_ns);
  t = next_tick(t, refresh_phase, c.refresh_ns);  // shown from the next refresh
  t += static_cast<std::int64_t>(c.photo_row * static_cast<double>(c.refresh_ns));  // the scan to the row
  t += path.uniform_int(c.pixel_min_ns, c.pixel_max_ns);
  return t + c.photo_rise_ns;
}

}  // namespace

void check(const FullLoopConfig& c) {
  auto bad = [](const char* field) {
    throw core::Error(core::ErrorKind::usage, fmt::format("full loop: {} is out of range", field));
  };
  check(c.gyro);
  if (c.manoeuvres < 1 || c.manoeuvres > 100'000) bad("manoeuvres");
  if (!(c.peak_min_deg_s > 0 && c.peak_min_deg_s <= c.peak_max_deg_s)) bad("peak_min_deg_s/peak_max_deg_s");
  const auto range = [&](std::int64_t lo, std::int64_t hi, const char* field, std::int64_t min_lo) {
    if (lo < min_lo || hi < lo) bad(field);
  };
  range(c.motion_min_ns, c.motion_max_ns, "motion_min_ns/motion_max_ns", 1);
  range(c.gap_min_ns, c.gap_max_ns, "gap_min_ns/gap_max_ns", 0);
  range(c.m2m_min_ns, c.m2m_max_ns, "m2m_min_ns/m2m_max_ns", 0);
  range(c.trigger_min_ns, c.trigger_max_ns, "trigger_min_ns/trigger_max_ns", 0);
  range(c.encode_min_ns, c.encode_max_ns, "encode_min_ns/encode_max_ns", 0);
  range(c.decode_min_ns, c.decode_max_ns, "decode_min_ns/decode_max_ns", 0);
  range(c.pixel_min_ns, c.pixel_max_ns, "pixel_min_ns/pixel_max_ns", 0);
  if (c.led_write_ns < 0) bad("led_write_ns");
  if (c.frame_ns <= 0) bad("frame_ns");
  if (c.exposure_ns < 0 || c.exposure_ns > c.frame_ns) bad("exposure_ns");
  if (c.network_ns < 0 || c.network_jitter_ns < 0) bad("network_ns/network_jitter_ns");
  if (c.refresh_ns <= 0) bad("refresh_ns");
  if (!(c.photo_row >= 0 && c.photo_row <= 1)) bad("photo_row");
  if (c.photo_rise_ns < 0) bad("photo_rise_ns");
  if (c.irq_mean_ns < 0) bad("irq_mean_ns");
  if (c.sync_max_ns < 0) bad("sync_max_ns");
}

FullLoopRun simulate_full_loop(const FullLoopConfig& config) {
  check(config);
  FullLoopRun run;
  run.config = config;
  const auto& c = config;
  Rng plan(c.seed, kLoopStreams + kPlan), clocks(c.seed, kLoopStreams + kClocks),
      path(c.seed, kLoopStreams + kPath);
  run.station_offset_ns = clocks.uniform_int(-c.sync_max_ns, c.sync_max_ns);
  run.vehicle_offset_ns =
      c.single_board ? run.station_offset_ns : clocks.uniform_int(-c.sync_max_ns, c.sync_max_ns);
  const std::int64_t frame_phase = path.uniform_int(0, c.frame_ns - 1);
  const std::int64_t refresh_phase = path.uniform_int(0, c.refresh_ns - 1);

  std::vector<RateMotion> station, vehicle;
  std::int64_t t = kStart;
  for (int k = 0; k < c.manoeuvres; ++k) {
    FullLoopManoeuvre m;
    const double peak = plan.uniform(c.peak_min_deg_s, c.peak_max_deg_s);
    const std::int64_t duration = plan.uniform_int(c.motion_min_ns, c.motion_max_ns);
    const int direction = plan.bernoulli(0.5) ? 1 : -1;
    const std::int64_t delay = plan.uniform_int(c.m2m_min_ns, c.m2m_max_ns);
    const std::int64_t trigger = plan.uniform_int(c.trigger_min_ns, c.trigger_max_ns);
    const std::int64_t gap = plan.uniform_int(c.gap_min_ns, c.gap_max_ns);
    std::int64_t write_begin = t;  // single board: the LED on its schedule
    std::int64_t busy_until = t + duration;
    if (!c.single_board) {
      m.station = hand_motion(t, peak, duration, direction);
      m.vehicle = c.baseline ? m.station : actuator_motion(m.station, delay, c.actuator);
      station.push_back(m.station);
      vehicle.push_back(m.vehicle);
      write_begin = m.vehicle.onset_ns + trigger;
      busy_until = std::max(m.station.end_ns(), m.vehicle.end_ns());
    }
    // The write takes effect somewhere between the stamps taken before and after it.
    m.led_true_ns = write_begin + plan.uniform_int(0, c.led_write_ns);
    m.led_stamp_ns = write_begin + c.led_write_ns / 2 + run.vehicle_offset_ns;
    m.led_bound_ns = c.led_write_ns - c.led_write_ns / 2;  // the larger half: the bound holds
    m.photo_true_ns = photo_edge(c, m.led_true_ns, frame_phase, refresh_phase, path);
    const auto irq = static_cast<std::int64_t>(static_cast<double>(c.irq_mean_ns) * path.exponential());
    m.photo_stamp_ns = m.photo_true_ns + irq + run.station_offset_ns;
    run.manoeuvres.push_back(m);
    t = std::max(busy_until, m.photo_true_ns) + gap;
  }
  run.end_ns = t;
  if (!c.single_board) {
    run.station_trace = simulate_gyro(c.gyro, station, 0, t, c.seed, kStationChip);
    run.vehicle_trace = simulate_gyro(c.gyro, vehicle, 0, t, c.seed, kVehicleChip);
    for (auto& s : run.station_trace.samples) s.time_ns += run.station_offset_ns;
    for (auto& s : run.vehicle_trace.samples) s.time_ns += run.vehicle_offset_ns;
  }
  return run;
}

std::optional<FullLoopConfig> full_loop_preset(std::string_view name) {
  FullLoopConfig c;
  if (name == "full_loop") return c;
  if (name == "full_loop_baseline") {
    c.baseline = true;
    return c;
  }
  if (name == "full_loop_single_board") {
    c.single_board = true;
    return c;
  }
  return std::nullopt;
}

std::vector<FullLoopClockSample> board_clock_samples(const FullLoopRun& run, bool station) {
  const std::int64_t bound = run.config.sync_max_ns;
  const auto u = static_cast<std::int64_t>(std::llround(static_cast<double>(bound) / std::sqrt(3.0)));
  const std::int64_t offset = station ? run.station_offset_ns : run.vehicle_offset_ns;
  std::vector<FullLoopClockSample> out;
  for (std::int64_t t = 0; t <= run.end_ns + 1'000'000'000; t += 1'000'000'000)
    out.push_back({t + offset, bound, u});
  return out;
}

}  // namespace m2mlat::sim
