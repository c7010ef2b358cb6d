// Sequence continuity with modular arithmetic, so that a 32-bit counter's wrap is no gap.
#include "m2mlat/capture/sequence_tracker.hpp"

#include <limits>

namespace m2mlat::capture {

SequenceTracker::SequenceTracker(std::uint64_t first_expected, unsigned wrap_bits)
    : expected_(first_expected),
      mask_(wrap_bits >= 64 ? std::numeric_limits<std::uint64_t>::max()
                            : (std::uint64_t{1} << wrap_bits) - 1) {}

std::optional<SequenceTracker::Missing> SequenceTracker::observe(std::uint64_t value) {
  value &= mask_;
  const bool started = last_.has_value() || expected_ != 0;
  std::optional<Missing> missing;
  if (started) {
    const std::uint64_t ahead = (value - expected_) & mask_;
    // Less than half the counter's range ahead: numbers were skipped. More: the value is behind
    // (a repeat or a restart), which is no loss.
    if (ahead != 0 && ahead <= (mask_ >> 1)) {
      missing = Missing{expected_, ahead};
      missing_total_ += ahead;
    }
  }
  last_ = value;
  expected_ = (value + 1) & mask_;
  return missing;
}

}  // namespace m2mlat::capture
