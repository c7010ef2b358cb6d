#include "m2mlat/analysis/scenario_breakdown.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::analysis {

void attach_breakdown(ScenarioResult& result, const StageRule& rule, const MarkerIndex& index) {
  std::vector<std::int64_t> cause_ns, effect_ns, ids;
  std::vector<std::size_t> positions;
  const auto times = result.times();
  for (std::size_t i = 0; i < result.match.pairs.size(); ++i) {
    if (!result.in_statistics(i)) continue;
    const auto& p = result.match.pairs[i];
    cause_ns.push_back(times.cause(p));
    effect_ns.push_back(times.effect(p));
    positions.push_back(i);
    ids.push_back(result.cause_seq(p));
  }
  try {
    result.breakdown = break_down(cause_ns, effect_ns, result.match.clock, positions, ids, rule, index);
  } catch (const core::Error& e) {
    throw core::Error(e.kind(), fmt::format("scenario {}: {}", core::printable(result.input.scenario), e.what()));
  }
}

}  // namespace m2mlat::analysis
