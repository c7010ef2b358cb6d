// Refractory filter against contact bounce: after an edge is kept, further edges on the same side
// within `period` are bounces. A Hall sensor (or a mechanical switch) can fire a few extra edges within
// a few ms of the true one; the first edge is the one whose timestamp is the motion's.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::pairing {

struct RefractoryResult {
  std::vector<std::int64_t> kept;     // indices into the input of the edges kept
  std::vector<std::int64_t> bounces;  // indices into the input of the edges suppressed
};

// `times_ns` must be sorted ascending (one clock). period <= 0 keeps everything.
// The period is measured from the last KEPT edge, so a long burst of bounces cannot extend itself.
RefractoryResult refractory_filter(std::span<const std::int64_t> times_ns, core::Duration period);

}  // namespace m2mlat::pairing
