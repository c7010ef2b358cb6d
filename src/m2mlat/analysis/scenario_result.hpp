// One scenario analysed: its pairs (with the unmatched events and their reasons) and the latency
// statistics. Everything here is recomputed from raw events: nothing derived is stored.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/analysis/board_record.hpp"
#include "m2mlat/analysis/breakdown.hpp"
#include "m2mlat/analysis/clock_steps.hpp"
#include "m2mlat/analysis/flagged_effect.hpp"
#include "m2mlat/analysis/sanity.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"

namespace m2mlat::analysis {

struct ScenarioResult {
  ScenarioInput input;
  pairing::MatchResult match;  // indices in match refer to input.cause / input.effect positions
  // Over the pairs not flagged ambiguous (all pairs with include_ambiguous); sample ids are the cause
  // events' seq (store) or index (files).
  stats::Summary summary;
  bool include_ambiguous = false;
  std::size_t ambiguous_pairs() const;
  // The median and IQR with the flagged pairs and without them; unset when none is flagged.
  std::optional<FlaggedEffect> flagged_effect;
  // One per match.pairs entry when the boards' clock samples are known (analysis/uncertainty.hpp),
  // else empty. With refuse_gated, pairs flagged by the sync gate leave the summary.
  std::vector<SampleUncertainty> uncertainty;
  bool refuse_gated = false;
  // What the store recorded on the two boards (analysis/board_record.hpp); empty for data files.
  std::vector<ClockSeries> clocks;  // one per node with clock samples on the events' clock
  std::vector<LossCount> losses;
  // Median of each board's own clock bound at its event times over the pairs kept by the ambiguity
  // choice (ms): the error budget. Unset when a board has no clock samples.
  std::optional<double> cause_clock_ms, effect_clock_ms;
  // What the boards' clock steps did to each event (clock_steps.hpp; parallel to input.cause and
  // input.effect): corrected onto the timescale before the step, or of unknown offset.
  ScenarioSteps steps;
  // Where the time goes, stage by stage, when a stage rule and markers were given
  // (scenario_breakdown.hpp): over the pairs in_statistics.
  std::optional<Breakdown> breakdown;
  // What makes the figures implausible, with its evidence (sanity.hpp): every output shows them.
  std::vector<SanityWarning> warnings;
  StepMark step_mark(const pairing::Pair& p) const;  // the worse of the pair's two events
  std::size_t pairs_marked(StepMark mark) const;     // unknown ones are flagged, out of the statistics
  // Whether match.pairs[i] is one of the pairs the summary is over (not ambiguous unless
  // include_ambiguous, not gated when refused, not after a clock step of unknown offset).
  bool in_statistics(std::size_t i) const;
  // Whether match.pairs[i] would be in the statistics whatever its pairing flags: not gated when refused,
  // not after a clock step of unknown offset; and if not, why (after_clock_step, sync_gated; else empty).
  bool admitted(std::size_t i) const;
  std::string_view not_admitted(std::size_t i) const;
  // Why match.pairs[i] is not in the statistics: its lowest pairing flag's name (ambiguous, competing,
  // jump, bounced, improbable), after_clock_step or sync_gated; empty when it is in.
  std::string_view left_out(std::size_t i) const;

  // The pairs' times: the input's columns, which the matcher paired (after correct_scenario).
  pairing::PairTimes times() const { return {input.cause.t_ns, input.effect.t_ns}; }
  std::vector<std::int64_t> latencies_ns() const;  // of the pairs the summary is over, in time order
  // Where each manoeuvre begins among latencies_ns() (manoeuvres.hpp): what the bootstrap resamples whole.
  std::vector<std::size_t> manoeuvre_starts() const;
  // The source ids (store seq or file index) of a pair's events, or of an unmatched event.
  std::int64_t cause_seq(const pairing::Pair& p) const { return source_id(input.cause, p.cause_index); }
  std::int64_t effect_seq(const pairing::Pair& p) const { return source_id(input.effect, p.effect_index); }
  std::int64_t seq(const pairing::Unmatched& u) const {
    return source_id(u.side == pairing::Side::cause ? input.cause : input.effect, u.index);
  }
};

// (Re)computes result.summary over the pairs in_statistics. The latencies are sorted in place and the
// sample ids looked up for the two extremes only, so while it runs it needs one column of 8 bytes a
// pair (74 MB at 9.3 M pairs) besides the result, not three.
void summarize(ScenarioResult& result, const stats::SummaryOptions& summary_options);

// Pairs the input and summarises the latencies of the pairs that are not ambiguous (or of all pairs).
ScenarioResult analyse(ScenarioInput input, const pairing::MatchOptions& match_options,
                       const stats::SummaryOptions& summary_options, bool include_ambiguous = false);
// The same for an input whose timestamps correct_scenario corrected, with its marks.
ScenarioResult analyse(ScenarioInput input, ScenarioSteps steps, const pairing::MatchOptions& match_options,
                       const stats::SummaryOptions& summary_options, bool include_ambiguous = false);

}  // namespace m2mlat::analysis
