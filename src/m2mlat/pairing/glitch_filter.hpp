// Interference filter for a line recorded with both edges: an edge to the active level starts a magnet
// pass only when the line then stays at that level. A Hall switch (A3144) holds its output low while
// the magnet is over the sensor, for milliseconds at any steering speed (a field 5 degrees wide passing
// at 360 deg/s: 14 ms), and interference on the wire gives a pulse of microseconds. With one edge per
// pass (the reference rig's kernel log) such a pulse is an edge like any other, and one that falls
// where a missed pass's edge would have been makes a pair no rule can tell from a true one
// (docs/matcher.md, "Limits"); with both edges its width gives it away.
//
// The rule, for a window w (`--min-pulse`), on the line's edges of both kinds in time order: an active
// edge starts no pass when
// - the line is back at idle within w and then stays idle for at least 2 w (an isolated short pulse:
//   interference), or
// - it ends a return to idle shorter than w after the line was active for at least 2 w (the line
//   dropping out for a moment inside a pass, or the chatter of its release).
// A pass's contact chatter (edges of both kinds less than 2 w apart, in its first milliseconds) is
// neither: its first active edge is the pass's, its later ones are left to the refractory filter as
// bounces. (With "at least w" instead of 2 w, a pass whose first bounce came 2 ms later, the line up
// half-way, lost its edge at w = 1 ms: the simulator's seed 168.)
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
