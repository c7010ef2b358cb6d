// Pair one scenario's events and summarise the latencies.
#include "m2mlat/analysis/scenario_result.hpp"

#include <algorithm>

namespace m2mlat::analysis {

std::vector<std::int64_t> ScenarioResult::latencies_ns() const {
  std::vector<std::int64_t> out;
  out.reserve(match.pairs.size());
  for (const auto& p : match.pairs)
    if (include_ambiguous || !p.ambiguous()) out.push_back(p.latency().count());
  return out;
}

std::size_t ScenarioResult::ambiguous_pairs() const {
  return static_cast<std::size_t>(
      std::count_if(match.pairs.begin(), match.pairs.end(), [](const auto& p) { return p.ambiguous(); }));
}

ScenarioResult analyse(ScenarioInput input, const pairing::MatchOptions& match_options,
                       const stats::SummaryOptions& summary_options, bool include_ambiguous) {
  ScenarioResult result;
  result.match = pairing::match(input.cause.t_ns, input.effect.t_ns, input.clock, match_options);
  result.input = std::move(input);
  result.include_ambiguous = include_ambiguous;
  const auto latencies = result.latencies_ns();
  std::vector<std::int64_t> ids;
  ids.reserve(latencies.size());
  for (const auto& p : result.match.pairs)
    if (include_ambiguous || !p.ambiguous()) ids.push_back(result.cause_seq(p));
  result.summary = stats::summarize(latencies, ids, summary_options);
  return result;
}

}  // namespace m2mlat::analysis
