// Manoeuvres from the gaps between the pairs' cause edges.
#include "m2mlat/analysis/manoeuvres.hpp"

namespace m2mlat::analysis {

std::vector<std::size_t> manoeuvre_starts(std::span<const std::int64_t> cause_ns, core::Duration gap) {
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < cause_ns.size(); ++i)
    if (i == 0 || cause_ns[i] < cause_ns[i - 1] || cause_ns[i] - cause_ns[i - 1] >= gap.count()) starts.push_back(i);
  return starts;
}

}  // namespace m2mlat::analysis
