// A scenario's pairing counts from its match and its statistics.
#include "m2mlat/analysis/pairing_counts.hpp"

namespace m2mlat::analysis {

PairingCounts pairing_counts(const ScenarioResult& r) {
  PairingCounts c;
  c.cause.edges = static_cast<std::size_t>(r.match.cause_count);
  c.effect.edges = static_cast<std::size_t>(r.match.effect_count);
  for (const auto& u : r.match.unmatched) {
    auto& side = u.side == pairing::Side::cause ? c.cause : c.effect;
    switch (u.reason) {
      case pairing::UnmatchedReason::bounce: ++side.bounces; break;
      case pairing::UnmatchedReason::no_candidate: ++side.no_candidate; break;
      case pairing::UnmatchedReason::outmatched: ++side.outmatched; break;
    }
  }
  c.pairs = r.match.pairs.size();
  c.flagged = r.ambiguous_pairs();
  c.in_statistics = r.summary.n;
  return c;
}

}  // namespace m2mlat::analysis
