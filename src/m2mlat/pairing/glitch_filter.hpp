// Interference filter for a line recorded with both edges: an edge to the active level starts a magnet
// pass only when the line then stays at that level. A Hall switch (A3144) holds its output low while
// the magnet is over the sensor, for milliseconds at any steering speed (a field 5 degrees wide passing
// at 360 deg/s: 14 ms), and interference on the wire gives a pulse of microseconds. With one edge per
// pass (the reference rig's kernel log) such a pulse is an edge like any other, and one that falls
// where a missed pass's edge would have been makes a pair no rule can tell from a true one
// (docs/matcher.md, "Limits"); with both edges its width gives it away.
//
// The rule, for a window w (`--min-pulse`): an active edge at t is a pass's when the line is at the
// active level for at least half of [t, t + w] and was at the idle level for at least half of
// [t - w, t]. An isolated short pulse fails the first; the line dropping to idle for a moment inside
// a pass (and back) fails the second; a pass's contact chatter (edges of both kinds in its first
// milliseconds) passes both, its later active edges being left to the refractory filter as bounces.
// The level before the first edge is taken to be idle.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::pairing {

// `active_ns` and `idle_ns`: one line's edges to its active and to its idle level, each sorted
// ascending (one clock). Returns the ascending indices into `active_ns` of the edges that start no
// pass. `min_pulse` <= 0 returns none.
std::vector<std::int64_t> glitches(std::span<const std::int64_t> active_ns,
                                   std::span<const std::int64_t> idle_ns, core::Duration min_pulse);

}  // namespace m2mlat::pairing
