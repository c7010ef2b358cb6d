// The simulated gyroscope and its polling reader: see gyro.hpp.
#include "m2mlat/sim/gyro.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>  // sqrt, llround: exact
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly
#include "m2mlat/core/portable_math.hpp"
#include "m2mlat/sim/random.hpp"

namespace m2mlat::sim {

namespace {
// Stream numbers within a chip: fixed forever, or every seed's traces change.
constexpr std::uint64_t kGyroStreams = 0x6779'0000;  // "gy"
enum : std::uint64_t { kMount = 0, kNoise = 1, kWalk = 2, kReader = 3 };
Rng stream(std::uint64_t seed, std::uint64_t chip, std::uint64_t concern) {
  return Rng(seed, kGyroStreams + chip * 8 + concern);
}
}  // namespace

double GyroConfig::noise_sd_deg_s() const { return noise_density_deg_s_rthz * std::sqrt(noise_bandwidth_hz); }

void check(const GyroConfig& c) {
  auto bad = [](const char* field) {
    throw core::Error(core::ErrorKind::usage, fmt::format("gyroscope: {} is out of range", field));
  };
  if (!(c.noise_density_deg_s_rthz >= 0)) bad("noise_density_deg_s_rthz");
  if (!(c.noise_bandwidth_hz > 0)) bad("noise_bandwidth_hz");
  if (!(c.bias_sd_deg_s >= 0)) bad("bias_sd_deg_s");
  if (!(c.bias_walk_deg_s_rts >= 0)) bad("bias_walk_deg_s_rts");
  if (!(c.clock_error_sd >= 0 && c.clock_error_sd < 0.1)) bad("clock_error_sd");
  if (!(c.tilt_sd >= 0 && c.tilt_sd < 1)) bad("tilt_sd");
  if (!(c.counts_per_deg_s > 0)) bad("counts_per_deg_s");
  if (c.period_ns <= 0) bad("period_ns");
  if (c.read_ns < 0) bad("read_ns");
  if (c.jitter_ns < 0) bad("jitter_ns");
}

core::RateTrace simulate_gyro(const GyroConfig& config, std::span<const RateMotion> motions,
                              std::int64_t from_ns, std::int64_t to_ns, std::uint64_t seed,
                              std::uint64_t chip) {
  check(config);
  core::RateTrace trace;
  trace.clock = core::Clock::simulated;
  trace.counts_per_deg_s = config.counts_per_deg_s;
  if (to_ns <= from_ns) return trace;

  // The chip: mounting axis, bias, sample clock and phase, drawn once.
  Rng mount = stream(seed, chip, kMount);
  std::array<double, 3> axis{config.tilt_sd * mount.normal(), config.tilt_sd * mount.normal(), 1.0};
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (auto& v : axis) v /= norm;
  std::array<double, 3> bias{};
  for (auto& b : bias) b = config.bias_sd_deg_s * mount.normal();
  const double period = static_cast<double>(config.period_ns) * (1 + config.clock_error_sd * mount.normal());
  const double phase = mount.uniform() * period;  // ns after from_ns of the chip's first sample

  Rng noise = stream(seed, chip, kNoise);
  Rng walk = stream(seed, chip, kWalk);
  Rng reader = stream(seed, chip, kReader);
  // The chip's noise is white noise through its first-order low-pass of noise_bandwidth_hz / (pi/2)
  // cut-off: neighbouring samples at 8 kHz are correlated, as on the chip. The white noise's sd is
  // chosen so the filtered noise has noise_sd_deg_s().
  const double cutoff_hz = config.noise_bandwidth_hz / 1.5707963267948966;
  const double pole = core::portable_exp(-2 * 3.141592653589793 * cutoff_hz * period * 1e-9);
  const double gain = 1 - pole;
  const double sd = config.noise_sd_deg_s() * std::sqrt((2 - gain) / gain);
  std::array<double, 3> coloured{};
  const double step_sd = config.bias_walk_deg_s_rts * std::sqrt(period * 1e-9);
  const double limit = 32767;

  // The reader's bound on a reading's age: one period of the chip's clock, whose tolerance is taken as 2%.
  const std::int64_t max_age = config.period_ns + config.period_ns / 50;
  trace.samples.reserve(static_cast<std::size_t>((to_ns - from_ns) / config.period_ns) + 1);
  std::size_t first_active = 0;  // motions before this one have ended
  std::size_t next_chip = 0;     // the chip's next sample to take
  std::array<std::int16_t, 3> latest{};
  std::int64_t scheduled = from_ns + std::llround(reader.uniform() * static_cast<double>(config.period_ns));
  std::int64_t previous_after = std::numeric_limits<std::int64_t>::min();
  auto jitter = [&]() -> std::int64_t {
    return std::llround(static_cast<double>(config.jitter_ns) * reader.exponential());
  };
  for (;; scheduled += config.period_ns) {
    // The poll: woken late by the scheduler, it stamps `before`; the bus read latches the registers a
    // little later and is done at `after`. A poll never starts before the previous one ended.
    const std::int64_t before = std::max(scheduled + jitter(), previous_after + 1);
    const std::int64_t latch = before + jitter();
    const std::int64_t after = latch + config.read_ns;
    if (latch >= to_ns) break;
    previous_after = after;
    // The chip's samples up to the latch (the register keeps the newest; others are never seen).
    for (;; ++next_chip) {
      const std::int64_t t = from_ns + std::llround(phase + static_cast<double>(next_chip) * period);
      if (t > latch) break;
      while (first_active < motions.size() && motions[first_active].end_ns() <= t) ++first_active;
      double rate = 0;
      for (std::size_t m = first_active; m < motions.size() && motions[m].onset_ns <= t; ++m)
        rate += rate_deg_s(motions[m], t);
      for (std::size_t a = 0; a < 3; ++a) {
        bias[a] += step_sd * walk.normal();
        coloured[a] += gain * (sd * noise.normal() - coloured[a]);
        const double counts = (rate * axis[a] + bias[a] + coloured[a]) * config.counts_per_deg_s;
        latest[a] = static_cast<std::int16_t>(std::llround(std::clamp(counts, -limit - 1, limit)));
      }
    }
    if (next_chip == 0) continue;  // the chip has not sampled yet
    const std::int64_t earliest = before - max_age;
    core::RateSample sample;
    sample.raw = latest;
    sample.time_ns = earliest + (after - earliest) / 2;
    sample.bound_ns = static_cast<std::int32_t>((after - earliest + 1) / 2);
    trace.samples.push_back(sample);
  }
  return trace;
}

}  // namespace m2mlat::sim
