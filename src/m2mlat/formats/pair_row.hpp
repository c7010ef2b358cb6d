// One row of a pairs file (m2mlat-pairs/4, the reference rig's paired CSV): a cause edge and the
// effect edge it is paired with. formats' own type, kept apart from the matcher's in-memory
// pairing::Pair so that the file layer depends on core only; analysis/pairs_file.hpp turns the
// matcher's pairs into rows.
#pragma once

#include <cstdint>

#include "m2mlat/core/time.hpp"

namespace m2mlat::formats {

struct PairRow {
  std::int64_t cause_index = 0;   // the cause event's index in the file's (or the caller's) event list
  std::int64_t effect_index = 0;  // the effect event's index likewise
  core::TimePoint cause_time;
  core::TimePoint effect_time;
  std::uint32_t flags = 0;  // pairing::PairFlag bits, written as given (1 = ambiguous burst)

  core::Duration latency() const { return effect_time - cause_time; }  // effect - cause, exact ns
  friend bool operator==(const PairRow&, const PairRow&) = default;
};

}  // namespace m2mlat::formats
