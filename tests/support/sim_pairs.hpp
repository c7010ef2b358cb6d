// A simulated run's true pairs as the matcher's pairs (the passes detected on both sides, each with
// its two events' timestamps), for tests that feed the analysis the truth instead of a matching.
// Included as "sim_pairs.hpp" (tests/support is on every test's include path).
#pragma once

#include <cstddef>

#include "m2mlat/pairing/pair.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::testing {

inline pairing::Pair true_pair(const sim::Simulation& run, const sim::TruePair& t) {
  pairing::Pair p;
  p.cause_index = static_cast<std::uint32_t>(t.cause_index);
  p.effect_index = static_cast<std::uint32_t>(t.effect_index);
  p.cause_ns = run.cause_events[static_cast<std::size_t>(t.cause_index)].time.ns();
  p.effect_ns = run.effect_events[static_cast<std::size_t>(t.effect_index)].time.ns();
  return p;
}

}  // namespace m2mlat::testing
