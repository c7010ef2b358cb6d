#include "m2mlat/pairing/glitch_filter.hpp"

#include <cstddef>
#include <limits>

namespace m2mlat::pairing {

std::vector<std::int64_t> glitches(std::span<const std::int64_t> active_ns,
                                   std::span<const std::int64_t> idle_ns, core::Duration min_pulse) {
  std::vector<std::int64_t> out;
  const std::int64_t w = min_pulse.count();
  if (w <= 0 || active_ns.empty()) return out;
  // The merged timeline: when, and whether the line went active. At equal times the active edge
  // first, so that a pulse of zero width (both edges stamped alike) ends idle.
  struct Change {
    std::int64_t t_ns;
    bool active;
  };
  std::vector<Change> changes;
  changes.reserve(active_ns.size() + idle_ns.size());
  for (std::size_t a = 0, i = 0; a < active_ns.size() || i < idle_ns.size();) {
    if (a < active_ns.size() && (i == idle_ns.size() || active_ns[a] <= idle_ns[i]))
      changes.push_back({active_ns[a++], true});
    else
      changes.push_back({idle_ns[i++], false});
  }
  // The time from change k to the next one, or to the end of the recording (held ever after).
  const auto held = [&](std::size_t k) {
    return k + 1 < changes.size() ? changes[k + 1].t_ns - changes[k].t_ns
                                  : std::numeric_limits<std::int64_t>::max();
  };
  const std::int64_t rest = 2 * w;  // the isolation a short pulse or a short dropout must have
  // The active edges in `changes` come in the order of `active_ns`: the a-th is active_ns[a].
  for (std::size_t k = 0, a = 0; k < changes.size(); ++k) {
    if (!changes[k].active) continue;
    const bool short_pulse =
        k + 1 < changes.size() && !changes[k + 1].active && held(k) < w && held(k + 1) >= rest;
    const bool short_dropout =
        k >= 2 && !changes[k - 1].active && changes[k - 2].active && held(k - 1) < w && held(k - 2) >= rest;
    if (short_pulse || short_dropout) out.push_back(static_cast<std::int64_t>(a));
    ++a;
  }
  return out;
}

}  // namespace m2mlat::pairing
