// The counts of one scenario's pairing, each with one meaning, in one place: every table, JSON member
// and live view that prints a count takes it from here, so that "pairs", "unmatched" and "bounces" mean
// the same in all of them (docs/statistics.md, "What the counts count").
#pragma once

#include <cstddef>

#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::analysis {

struct SideCounts {
  std::size_t edges = 0;         // given to the matcher (after the interference filter, whose drops are
                                 // ScenarioInput::glitches)
  std::size_t bounces = 0;       // dropped as bounces within the refractory period of a kept edge
  std::size_t no_candidate = 0;  // not bounces, no edge of the other side within the window
  std::size_t outmatched = 0;    // not bounces, candidates taken by a better alignment
  std::size_t unpaired() const { return no_candidate + outmatched; }  // edges without partner, bounces apart
};

struct PairingCounts {
  SideCounts cause, effect;
  std::size_t pairs = 0;          // pairs the matcher made
  std::size_t flagged = 0;        // of those, with a pairing flag (pairing::kPairUncertain)
  std::size_t in_statistics = 0;  // the pairs the statistics are over (summary.n)
  std::size_t bounces() const { return cause.bounces + effect.bounces; }
};

PairingCounts pairing_counts(const ScenarioResult& result);

}  // namespace m2mlat::analysis
