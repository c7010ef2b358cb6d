// Loading a scenario's clock samples and losses from the store, and what is derived from them.
#include "m2mlat/analysis/board_record.hpp"

#include <algorithm>
#include <map>
#include <optional>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

namespace {

std::optional<double> median_ms(std::vector<std::int64_t> ns) {
  if (ns.empty()) return std::nullopt;
  return stats::median(std::move(ns)) / 1e6;
}

// The node's samples on `clock`, in time order (sessions of one node follow each other, but a
// merged store may interleave them).
ClockSeries series_of(const std::string& node, const std::vector<store::ClockSample>& samples,
                      core::Clock clock) {
  std::vector<const store::ClockSample*> on_clock;
  for (const auto& s : samples)
    if (s.time.clock() == clock) on_clock.push_back(&s);
  std::stable_sort(on_clock.begin(), on_clock.end(),
                   [](const auto* a, const auto* b) { return a->time.ns() < b->time.ns(); });
  ClockSeries series{node, {}, {}, {}, {}};
  // The source named is that of the first sample recorded on the clock, before sorting.
  const auto first = std::find_if(samples.begin(), samples.end(),
                                  [&](const store::ClockSample& s) { return s.time.clock() == clock; });
  if (first != samples.end()) series.source = first->source;
  for (const auto* s : on_clock) {
    series.t_ns.push_back(s->time.ns());
    series.offset_ns.push_back(s->offset_ns);
    series.max_error_ns.push_back(s->max_error_ns);
  }
  return series;
}

// The medians of each board's own bound (bound_at, the rule of uncertainty.hpp) at its event time
// over the pairs the summary's ambiguity choice keeps: which board the error budget is spent on.
void attach_budget(ScenarioResult& result, const ClockTrack& cause, const ClockTrack& effect,
                   double growth_ppm) {
  result.cause_clock_ms.reset();
  result.effect_clock_ms.reset();
  if (cause.empty() || effect.empty()) return;
  std::vector<std::int64_t> cause_bounds, effect_bounds;
  const auto times = result.times();
  for (const auto& p : result.match.pairs) {
    if (!result.include_ambiguous && p.ambiguous()) continue;
    const auto bc = bound_at(cause, times.cause(p), growth_ppm);
    const auto be = bound_at(effect, times.effect(p), growth_ppm);
    if (bc.synchronised) cause_bounds.push_back(bc.max_error_ns);
    if (be.synchronised) effect_bounds.push_back(be.max_error_ns);
  }
  result.cause_clock_ms = median_ms(std::move(cause_bounds));
  result.effect_clock_ms = median_ms(std::move(effect_bounds));
}

}  // namespace

std::span<const store::ClockSample> BoardRecord::of(const std::string& node) const {
  const auto it = samples.find(node);
  return it == samples.end() ? std::span<const store::ClockSample>{} : std::span(it->second);
}

void BoardRecord::add(const std::string& node, store::ClockSample sample) {
  if (auto lines = store::unknown_clock_of(sample))
    unknown_clock[node].push_back(std::move(*lines));
  else
    samples[node].push_back(std::move(sample));
}

BoardRecord read_board_record(const store::Store& store, const ScenarioInput& in) {
  BoardRecord record;
  std::map<std::pair<std::string, std::string>, LossCount> losses;
  for (const auto& session : store.sessions()) {
    if (session.scenario != in.scenario) continue;
    if (session.node != in.cause_ref.node && session.node != in.effect_ref.node) continue;
    record.samples[session.node];  // a node without samples is still a node of the record
    for (auto& sample : store.clock_samples(session.id)) record.add(session.node, std::move(sample));
    for (const auto& l : store.losses(session.id)) {
      auto& count = losses[{session.node, l.kind}];
      count.node = session.node;
      count.kind = l.kind;
      ++count.records;
      count.events += l.count;
    }
  }
  for (const auto& entry : losses) record.losses.push_back(entry.second);
  return record;
}

void attach_board_record(ScenarioResult& result, const BoardRecord& record, const UncertaintyOptions& options,
                         const stats::SummaryOptions& summary_options) {
  const auto& in = result.input;
  result.clocks.clear();
  for (const auto& [node, node_samples] : record.samples)
    if (auto series = series_of(node, node_samples, in.clock); !series.t_ns.empty())
      result.clocks.push_back(std::move(series));
  result.losses = record.losses;

  const auto track = [&](const std::string& node) {
    const auto part = record.of(node);
    auto t = make_clock_track(std::vector<store::ClockSample>(part.begin(), part.end()), in.clock);
    t.node = node;  // the model recognises a board that follows the other by its name
    return t;
  };
  const auto cause = track(in.cause_ref.node);
  const auto effect = track(in.effect_ref.node);
  attach_uncertainty(result, cause, effect, options, summary_options);
  // A pair after a step of unknown offset (clock_steps.hpp) is a clock-step sample too.
  if (result.steps.steps() != 0)
    for (std::size_t i = 0; i < result.uncertainty.size() && i < result.match.pairs.size(); ++i)
      if (result.step_mark(result.match.pairs[i]) == StepMark::unknown)
        result.uncertainty[i].flags |= kUncertaintyClockStep;
  attach_budget(result, cause, effect, options.growth_ppm);
}

void attach_board_record(ScenarioResult& result, const store::Store& store, const UncertaintyOptions& options,
                         const stats::SummaryOptions& summary_options) {
  attach_board_record(result, read_board_record(store, result.input), options, summary_options);
}

}  // namespace m2mlat::analysis
