// The streaming form of pairing::refractory_filter, per channel in the recorder: after an edge is
// kept, edges within `period` of it are contact bounce and are counted, not stored. Measured from
// the last KEPT edge, as the offline filter does, so the two agree on the same edges.
#pragma once

#include <cstdint>
#include <optional>

#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

class RefractoryGate {
 public:
  explicit RefractoryGate(core::Duration period = core::Duration{0}) : period_(period) {}
  // True if the edge at `time` is kept. Times must not go backwards (the kernel's order).
  bool admit(core::TimePoint time);
  std::uint64_t suppressed() const { return suppressed_; }
  core::Duration period() const { return period_; }

 private:
  core::Duration period_;
  std::optional<core::TimePoint> last_kept_;
  std::uint64_t suppressed_ = 0;
};

}  // namespace m2mlat::capture
