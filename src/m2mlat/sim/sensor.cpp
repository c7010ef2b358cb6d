// Sensor imperfections: see sensor.hpp.
#include "m2mlat/sim/sensor.hpp"

#include <algorithm>
#include <cmath>  // llround: exact
#include <limits>

#include "m2mlat/core/fp_determinism.hpp"  // before any code: doubles follow IEEE rules exactly

namespace m2mlat::sim {

namespace {
// Stream numbers per side: fixed forever, or every seed's rig changes.
constexpr std::uint64_t kSensorStreamBase = 0x100;
constexpr std::uint64_t stream(core::Role role, std::uint64_t concern) {
  return kSensorStreamBase + 0x10 * static_cast<std::uint64_t>(role) + concern;
}
}  // namespace

SensorModel::SensorModel(const SensorConfig& config, std::uint64_t seed, core::Role role)
    : config_(config),
      detect_rng_(seed, stream(role, 1)),
      bounce_rng_(seed, stream(role, 2)),
      irq_rng_(seed, stream(role, 3)),
      spurious_rng_(seed, stream(role, 4)),
      rising_rng_(seed, stream(role, 5)) {}

bool SensorModel::detects() { return !detect_rng_.bernoulli(config_.miss_probability); }

void SensorModel::bounces(std::int64_t edge_ns, std::vector<std::int64_t>& out) {
  if (!bounce_rng_.bernoulli(config_.bounce_probability)) return;
  const std::int64_t extra = bounce_rng_.uniform_int(1, config_.bounce_max_extra);
  // Each gap is uniform in [min_gap, window / extra], so all of them fit in the window.
  const std::int64_t gap_min = config_.bounce_min_gap.count();
  const std::int64_t gap_max = std::max(gap_min, config_.bounce_window.count() / extra);
  std::int64_t t = edge_ns;
  for (std::int64_t i = 0; i < extra; ++i) {
    t += bounce_rng_.uniform_int(gap_min, gap_max);
    out.push_back(t);
  }
}

std::int64_t SensorModel::irq_latency() { return sample(config_.irq_latency, irq_rng_).count(); }

std::int64_t SensorModel::next_spurious(std::int64_t after_ns) {
  if (config_.spurious_per_minute <= 0) return std::numeric_limits<std::int64_t>::max();
  const double mean_gap_ns = 60e9 / config_.spurious_per_minute;
  // At least 1 ns later, so that two spurious edges never share a time.
  return after_ns + std::max<std::int64_t>(1, std::llround(mean_gap_ns * spurious_rng_.exponential()));
}

std::int64_t SensorModel::dwell() { return sample(config_.dwell, rising_rng_).count(); }
std::int64_t SensorModel::interference_width() {
  return sample(config_.interference_width, rising_rng_).count();
}
std::int64_t SensorModel::rising_irq_latency() { return sample(config_.irq_latency, rising_rng_).count(); }

}  // namespace m2mlat::sim
