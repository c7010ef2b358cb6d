// A simulated run's true pairs as the matcher's pairs (the passes detected on both sides, by their
// events' indices), for tests that feed the analysis the truth instead of a matching; the times are
// the columns of the run's events (event_times).
// Included as "sim_pairs.hpp" (tests/support is on every test's include path).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "m2mlat/pairing/pair.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::testing {

inline pairing::Pair true_pair(const sim::TruePair& t) {
  pairing::Pair p;
  p.cause_index = static_cast<std::uint32_t>(t.cause_index);
  p.effect_index = static_cast<std::uint32_t>(t.effect_index);
  return p;
}

// One side's event times (ns): the column its pairs' indices refer to.
inline std::vector<std::int64_t> event_times(const std::vector<core::Event>& events) {
  std::vector<std::int64_t> out;
  for (const auto& e : events) out.push_back(e.time.ns());
  return out;
}

}  // namespace m2mlat::testing
