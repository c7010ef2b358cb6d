// Pairing the same physical pulse edge seen by two boards (the synchronisation test): one output
// line wired to an input on each board, toggled every `period`. Both boards timestamp each edge on
// their own CLOCK_REALTIME; the pair's offset t_B - t_A is how far B's clock reads ahead of A's
// (plus the difference of the two interrupt latencies).
//
// Rule: a's edge and b's edge are the same pulse when each is the other's nearest (after shifting
// A's times by the expected offset) and they are less than half a period apart. Mutual nearest
// neighbours are one-to-one by construction, so a missing edge on one side leaves its partner
// unmatched instead of shifting every later pair, and an extra edge (a glitch) loses to the real one
// unless it is closer. Offsets of half a period or more cannot be told from a neighbouring pulse:
// give the expected offset (e.g. from the sync daemon) when the clocks may be that far apart.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::pairing {

struct PulsePairingOptions {
  // The pulse period (time between the edges that are paired, ns). 0: the median interval between
  // A's successive edges.
  core::Duration period{0};
  core::Duration expected_offset{0};  // added to A's times before looking for the nearest B edge
};

struct PulsePair {
  std::size_t a_index = 0;  // position in the A input
  std::size_t b_index = 0;  // position in the B input
  std::int64_t a_ns = 0;    // A's timestamp, ns
  std::int64_t b_ns = 0;    // B's timestamp, ns
  std::int64_t offset_ns() const { return b_ns - a_ns; }
  friend bool operator==(const PulsePair&, const PulsePair&) = default;
};

struct PulsePairing {
  core::Duration period{0};              // the period used (given or estimated), ns
  std::vector<PulsePair> pairs;          // in A's time order
  std::vector<std::size_t> unmatched_a;  // positions in the A input, ascending by time
  std::vector<std::size_t> unmatched_b;
};

// The median interval between successive timestamps (of the sorted values); 0 for fewer than 2.
core::Duration median_interval(std::span<const std::int64_t> t_ns);

// a_ns, b_ns: the two boards' edge times, ns on the same clock (any order). Throws
// core::Error(usage) if the period is negative or cannot be estimated (fewer than 2 A edges).
PulsePairing pair_pulses(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns,
                         const PulsePairingOptions& options = {});

}  // namespace m2mlat::pairing
