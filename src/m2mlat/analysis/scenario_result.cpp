// Pair one scenario's events and summarise the latencies.
#include "m2mlat/analysis/scenario_result.hpp"

#include <algorithm>

#include "m2mlat/analysis/manoeuvres.hpp"

namespace m2mlat::analysis {

StepMark ScenarioResult::step_mark(const pairing::Pair& p) const {
  const auto c = steps.cause.at(static_cast<std::size_t>(p.cause_index));
  const auto e = steps.effect.at(static_cast<std::size_t>(p.effect_index));
  return std::max(c, e);
}

std::size_t ScenarioResult::pairs_marked(StepMark mark) const {
  if (steps.steps() == 0) return 0;
  return static_cast<std::size_t>(
      std::count_if(match.pairs.begin(), match.pairs.end(), [&](const auto& p) { return step_mark(p) == mark; }));
}

bool ScenarioResult::in_statistics(std::size_t i) const {
  return (include_ambiguous || !match.pairs[i].ambiguous()) && admitted(i);
}

bool ScenarioResult::admitted(std::size_t i) const { return not_admitted(i).empty(); }

std::string_view ScenarioResult::not_admitted(std::size_t i) const {
  if (steps.steps() != 0 && step_mark(match.pairs[i]) == StepMark::unknown) return "after_clock_step";
  if (refuse_gated && i < uncertainty.size() && uncertainty[i].gated()) return "sync_gated";
  return {};
}

std::string_view ScenarioResult::left_out(std::size_t i) const {
  const std::uint32_t flags = match.pairs[i].flags & pairing::kPairUncertain;
  if (include_ambiguous || flags == 0) return not_admitted(i);
  if (flags & pairing::kPairAmbiguous) return "ambiguous";
  if (flags & pairing::kPairCompeting) return "competing";
  if (flags & pairing::kPairJump) return "jump";
  if (flags & pairing::kPairBounced) return "bounced";
  return "improbable";
}

std::vector<std::int64_t> ScenarioResult::latencies_ns() const {
  std::vector<std::int64_t> out;
  out.reserve(match.pairs.size());
  const auto t = times();
  for (std::size_t i = 0; i < match.pairs.size(); ++i)
    if (in_statistics(i)) out.push_back(t.latency(match.pairs[i]).count());
  return out;
}

std::vector<std::size_t> ScenarioResult::manoeuvre_starts() const {
  std::vector<std::int64_t> causes;
  const auto t = times();
  for (std::size_t i = 0; i < match.pairs.size(); ++i)
    if (in_statistics(i)) causes.push_back(t.cause(match.pairs[i]));
  return analysis::manoeuvre_starts(causes, match.burst_gap);
}

std::size_t ScenarioResult::ambiguous_pairs() const {
  return static_cast<std::size_t>(
      std::count_if(match.pairs.begin(), match.pairs.end(), [](const auto& p) { return p.ambiguous(); }));
}

ScenarioResult analyse(ScenarioInput input, const pairing::MatchOptions& match_options,
                       const stats::SummaryOptions& summary_options, bool include_ambiguous) {
  return analyse(std::move(input), ScenarioSteps{}, match_options, summary_options, include_ambiguous);
}

ScenarioResult analyse(ScenarioInput input, ScenarioSteps steps, const pairing::MatchOptions& match_options,
                       const stats::SummaryOptions& summary_options, bool include_ambiguous) {
  ScenarioResult result;
  result.steps = std::move(steps);
  // `input` is this function's own: the matcher rearranges its columns while it runs (no copy of
  // them, 8 bytes an edge) and puts them back before it returns.
  result.match = pairing::match_in_place(input.cause.t_ns, input.effect.t_ns, input.clock, match_options);
  result.input = std::move(input);
  result.include_ambiguous = include_ambiguous;
  summarize(result, summary_options);
  result.warnings = sanity_warnings(result, match_options);
  return result;
}

void summarize(ScenarioResult& result, const stats::SummaryOptions& summary_options) {
  auto latencies = result.latencies_ns();
  const auto manoeuvres = summary_options.bootstrap ? result.manoeuvre_starts() : std::vector<std::size_t>{};
  auto& summary = result.summary = stats::summarize_in_place(latencies, {}, summary_options, manoeuvres);
  {
    std::vector<std::int64_t> flagged;  // the flagged pairs' latencies: in the sorted sample or not
    const auto t = result.times();
    for (std::size_t i = 0; i < result.match.pairs.size(); ++i)
      if (result.match.pairs[i].ambiguous() && result.admitted(i))
        flagged.push_back(t.latency(result.match.pairs[i]).count());
    std::sort(flagged.begin(), flagged.end());
    result.flagged_effect = flagged_effect(latencies, flagged, result.include_ambiguous, summary.bootstrap);
  }
  if (!summary.min) return;
  // Without ids an extreme's id is its position among latencies_ns(); name the cause event instead.
  const auto last = std::max(summary.min->index, summary.max->index);
  std::size_t k = 0;  // position among the pairs in_statistics
  for (std::size_t i = 0; i < result.match.pairs.size() && k <= last; ++i) {
    if (!result.in_statistics(i)) continue;
    if (k == summary.min->index) summary.min->id = result.cause_seq(result.match.pairs[i]);
    if (k == summary.max->index) summary.max->id = result.cause_seq(result.match.pairs[i]);
    ++k;
  }
}

}  // namespace m2mlat::analysis
