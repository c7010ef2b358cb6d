// One side's Hall sensor and its imperfections: missed detections, contact bounce (extra edges a
// few ms after the true one), spurious edges (a Poisson process), and the interrupt latency between
// an edge and the kernel's timestamp. Each concern draws from its own random stream, so changing
// one probability leaves every other draw of the run as it was.
#pragma once

#include <cstdint>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/sim/random.hpp"
#include "m2mlat/sim/rig_config.hpp"

namespace m2mlat::sim {

class SensorModel {
 public:
  // `role`: cause or effect (selects the random streams); config must be valid.
  SensorModel(const SensorConfig& config, std::uint64_t seed, core::Role role);

  // Whether a magnet pass gives an edge (false with miss_probability).
  bool detects();
  // The true times of the bounce edges following an edge at `edge_ns` (usually none), appended
  // to `out` in increasing order.
  void bounces(std::int64_t edge_ns, std::vector<std::int64_t>& out);
  // Edge -> kernel timestamp, ns.
  std::int64_t irq_latency();
  // True time of the next spurious edge after `after_ns`; INT64_MAX when the rate is 0.
  std::int64_t next_spurious(std::int64_t after_ns);
  // With both edges (SensorConfig::both_edges): a pass's time at the active level, an interference
  // pulse's width, and the edge -> timestamp latency of the rising edges, ns.
  std::int64_t dwell();
  std::int64_t interference_width();
  std::int64_t rising_irq_latency();
  bool both_edges() const { return config_.both_edges; }

 private:
  const SensorConfig& config_;
  Rng detect_rng_;
  Rng bounce_rng_;
  Rng irq_rng_;
  Rng spurious_rng_;
  Rng rising_rng_;
};

}  // namespace m2mlat::sim
