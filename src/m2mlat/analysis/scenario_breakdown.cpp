#include "m2mlat/analysis/scenario_breakdown.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::analysis {

void attach_breakdown(ScenarioResult& result, const StageRule& rule, const MarkerIndex& index) {
  std::vector<pairing::Pair> pairs;
  std::vector<std::size_t> positions;
  std::vector<std::int64_t> ids;
  for (std::size_t i = 0; i < result.match.pairs.size(); ++i) {
    if (!result.in_statistics(i)) continue;
    const auto& p = result.match.pairs[i];
    pairs.push_back(p);
    positions.push_back(i);
    ids.push_back(result.cause_seq(p));
  }
  try {
    result.breakdown = break_down(pairs, result.match.clock, positions, ids, rule, index);
  } catch (const core::Error& e) {
    throw core::Error(e.kind(), fmt::format("scenario {}: {}", core::printable(result.input.scenario), e.what()));
  }
}

}  // namespace m2mlat::analysis
