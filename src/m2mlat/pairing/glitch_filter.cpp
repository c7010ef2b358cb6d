#include "m2mlat/pairing/glitch_filter.hpp"

#include <cstddef>

namespace m2mlat::pairing {
namespace {

// One edge of the merged timeline: when, and the level the line is at after it.
struct Change {
  std::int64_t t_ns;
  bool active;
};

// The time the line spends at the active level in [from, to], ns, walking the changes around `k`
// (the change at `from` or `to`). The level before changes[0] is idle.
std::int64_t active_time(const std::vector<Change>& changes, std::size_t k, std::int64_t from,
                         std::int64_t to) {
  std::size_t first = k;  // the last change at or before `from` (or none: the line was idle)
  while (first > 0 && changes[first].t_ns > from) --first;
  std::int64_t total = 0;
  bool active = changes[first].t_ns <= from && changes[first].active;
  std::int64_t at = from;
  for (std::size_t c = changes[first].t_ns <= from ? first + 1 : first;
       c < changes.size() && changes[c].t_ns <= to; ++c) {
    if (active) total += changes[c].t_ns - at;
    at = changes[c].t_ns;
    active = changes[c].active;
  }
  if (active) total += to - at;
  return total;
}

}  // namespace

std::vector<std::int64_t> glitches(std::span<const std::int64_t> active_ns,
                                   std::span<const std::int64_t> idle_ns, core::Duration min_pulse) {
  std::vector<std::int64_t> out;
  const std::int64_t w = min_pulse.count();
  if (w <= 0 || active_ns.empty()) return out;
  // The merged timeline; at equal times the active edge first, so that a pulse of zero width (both
  // edges stamped alike) ends idle.
  std::vector<Change> changes;
  changes.reserve(active_ns.size() + idle_ns.size());
  std::vector<std::size_t> position(active_ns.size());  // where each active edge is in `changes`
  for (std::size_t a = 0, i = 0; a < active_ns.size() || i < idle_ns.size();) {
    if (a < active_ns.size() && (i == idle_ns.size() || active_ns[a] <= idle_ns[i])) {
      position[a] = changes.size();
      changes.push_back({active_ns[a++], true});
    } else {
      changes.push_back({idle_ns[i++], false});
    }
  }
  // Half of a window, rounded up: "at least half" of an odd w.
  const std::int64_t half = w - w / 2;
  for (std::size_t a = 0; a < active_ns.size(); ++a) {
    const std::int64_t t = active_ns[a];
    const std::size_t k = position[a];
    const bool held = active_time(changes, k, t, t + w) >= half;
    const bool rested = w - active_time(changes, k, t - w, t) >= half;
    if (!held || !rested) out.push_back(static_cast<std::int64_t>(a));
  }
  return out;
}

}  // namespace m2mlat::pairing
