// Scenario results as JSON. NaN (undefined statistics) becomes null; exact values stay integer ns.
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"

#include "m2mlat/analysis/pairing_counts.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/formats/json_number.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/resampling_text.hpp"

namespace m2mlat::report {

using formats::number;

namespace {
nlohmann::json extreme(const std::optional<stats::Extreme>& e) {
  if (!e) return nullptr;
  return {{"ns", e->ns}, {"ms", e->ms()}, {"sample_id", e->id}};
}

nlohmann::json interval(const stats::Interval& i) { return nlohmann::json::array({i.lower, i.upper}); }

nlohmann::json resampling_json(const stats::Resampling& r) {
  return {{"resampled", resampling_name(r)},
          {"units", r.units},
          {"largest_unit", r.largest_unit},
          {"block_length", r.blocks.length},
          {"correlated_lags", r.blocks.reach},
          {"lag1_autocorrelation", number(r.blocks.lag1)},
          {"over_limit", r.over_limit},
          {"why", resampling_text(r)}};
}
}  // namespace

nlohmann::json summary_json(const stats::Summary& s) {
  nlohmann::json j{{"n", s.n},
                   {"min", extreme(s.min)},
                   {"max", extreme(s.max)},
                   {"mean_ms", number(s.mean_ms)},
                   {"sd_ms", number(s.sd_ms)},
                   {"p5_ms", number(s.p5_ms)},
                   {"q1_ms", number(s.q1_ms)},
                   {"median_ms", number(s.median_ms)},
                   {"q3_ms", number(s.q3_ms)},
                   {"p90_ms", number(s.p90_ms)},
                   {"p95_ms", number(s.p95_ms)},
                   {"p99_ms", number(s.p99_ms)},
                   {"iqr_ms", number(s.iqr_ms)}};
  auto& extra = j["percentiles"] = nlohmann::json::array();
  for (const auto& p : s.extra_percentiles)
    extra.push_back({{"percent", p.percent}, {"ms", number(p.value_ms)}});
  auto& above = j["above"] = nlohmann::json::array();
  for (const auto& t : s.thresholds)
    above.push_back({{"threshold_ns", t.threshold.count()},
                     {"count", t.count_above},
                     {"fraction", number(t.fraction_above)}});
  if (s.bootstrap)
    j["bootstrap"] = {{"level", s.bootstrap->level},
                      {"resamples", s.bootstrap->resamples},
                      {"seed", s.bootstrap->seed},
                      {"median_ms", interval(s.bootstrap->median_ms)},
                      {"iqr_ms", interval(s.bootstrap->iqr_ms)},
                      {"resampling", resampling_json(s.bootstrap->resampling)}};
  else
    j["bootstrap"] = nullptr;
  return j;
}

nlohmann::json pairing_json(const analysis::ScenarioResult& r) {
  const auto counts = analysis::pairing_counts(r);
  const auto side = [](const analysis::SideCounts& s) {
    return nlohmann::json{{"bounce", s.bounces}, {"no_candidate", s.no_candidate}, {"outmatched", s.outmatched}};
  };
  nlohmann::json j{{"cause_events", counts.cause.edges},
                   {"effect_events", counts.effect.edges},
                   {"pairs", counts.pairs},
                   {"ambiguous_pairs", counts.flagged},
                   {"in_statistics", counts.in_statistics},
                   {"ambiguous_in_statistics", r.include_ambiguous},
                   {"unmatched", {{"cause", side(counts.cause)}, {"effect", side(counts.effect)}}}};
  // Only with --matcher model: the fitted alignment model and what it expects of the pairs kept.
  if (const auto& m = r.match.model) {
    const auto& p = m->parameters;
    j["model"] = {{"latency_s", p.mean_s},       {"spread_s", p.spread_s},
                  {"correlation_time_s", p.tau_s}, {"stretch", p.stretch},
                  {"stretch_sd", p.stretch_sd}, {"jitter_s", p.jitter_s},
                  {"cause_loss", p.cause_loss},  {"unmatched_effects_per_s", p.unmatched_per_s},
                  {"fresh", p.reset},            {"iterations", m->iterations},
                  {"min_probability", m->min_probability}, {"kept", m->kept},
                  {"expected_wrong", m->expected_wrong}};
  }
  // Only with --min-pulse: edges dropped before pairing, not counted in cause_events / effect_events.
  if (const auto& g = r.input.glitches)
    j["glitches"] = {{"min_pulse_ns", g->min_pulse.count()}, {"cause", g->cause}, {"effect", g->effect}};
  // Only when the sanity verdict has something to say (analysis/sanity.hpp).
  if (!r.warnings.empty()) {
    auto& w = j["warnings"] = nlohmann::json::array();
    for (const auto& x : r.warnings) w.push_back({{"code", x.code}, {"text", x.text}});
  }
  // Only when a kernel log had lines on no known clock: their events, left out before pairing.
  const auto& c = r.input.cause_unknown_clock;
  const auto& e = r.input.effect_unknown_clock;
  if (c.total() + e.total() != 0)
    j["unknown_clock"] = {{"cause", {{"outlier", c.outlier}, {"before_sync", c.before_sync}}},
                          {"effect", {{"outlier", e.outlier}, {"before_sync", e.before_sync}}}};
  return j;
}

nlohmann::json uncertainty_json(const analysis::UncertaintySummary& s) {
  return {{"samples", s.samples},
          {"with_clock", s.known},
          {"bounded", s.bounded},
          {"median_u_ms", number(s.median_u_ms)},
          {"median_U95_ms", number(s.median_U95_ms)},
          {"median_max_err_ms", number(s.median_max_ms)},
          {"p95_max_err_ms", number(s.p95_max_ms)},
          {"worst_max_err_ms", number(s.worst_max_ms)},
          {"unsynchronised", s.unsynchronised},
          {"clock_step", s.clock_step},
          {"gated", s.gated},
          {"refused", s.refused},
          {"flagged", s.flagged},
          {"share_flagged", number(s.share_flagged())}};
}

// Only where a board's clock stepped: what the steps did to the pairs (analysis/clock_steps.hpp).
nlohmann::json clock_steps_json(const analysis::ScenarioResult& r) {
  return {{"cause_steps", r.steps.cause.steps},
          {"effect_steps", r.steps.effect.steps},
          {"pairs_corrected", r.pairs_marked(analysis::StepMark::corrected)},
          {"pairs_after_step", r.pairs_marked(analysis::StepMark::unknown)},
          {"fast_slew_places", r.steps.fast_slew_places()},
          {"notes", clock_limit_notes(r)}};
}

nlohmann::json scenario_json(const analysis::ScenarioResult& r) {
  nlohmann::json j{{"scenario", r.input.scenario},
                   {"cause", core::to_string(r.input.cause_ref)},
                   {"effect", core::to_string(r.input.effect_ref)},
                   {"clock", core::to_string(r.input.clock)},
                   {"sample_id", r.input.id_kind},
                   {"pairing", pairing_json(r)},
                   {"latency", summary_json(r.summary)}};
  if (!r.uncertainty.empty())
    j["sample_uncertainty"] =
        uncertainty_json(analysis::summarize_uncertainty(r.uncertainty, r.refuse_gated));
  if (r.steps.steps() != 0 || r.steps.limited()) j["clock_steps"] = clock_steps_json(r);
  if (r.breakdown) j["breakdown"] = breakdown_json(*r.breakdown);
  if (const auto& e = r.flagged_effect)
    j["flagged_effect"] = {{"flagged", e->flagged},
                           {"in_statistics", e->included},
                           {"without", {{"n", e->n_without}, {"median_ms", number(e->median_without_ms)},
                                        {"iqr_ms", number(e->iqr_without_ms)}}},
                           {"with", {{"n", e->n_with}, {"median_ms", number(e->median_with_ms)},
                                     {"iqr_ms", number(e->iqr_with_ms)}}},
                           {"median_moves", e->median_moves()},
                           {"iqr_moves", e->iqr_moves()}};
  return j;
}

nlohmann::json stats_document(std::span<const analysis::ScenarioResult> results) {
  nlohmann::json doc{{"format", kStatsFormat}, {"scenarios", nlohmann::json::array()}};
  for (const auto& r : results) doc["scenarios"].push_back(scenario_json(r));
  return doc;
}

nlohmann::json pairing_document(std::span<const analysis::ScenarioResult> results) {
  nlohmann::json doc{{"format", kStatsFormat}, {"scenarios", nlohmann::json::array()}};
  for (const auto& r : results) {
    doc["scenarios"].push_back({{"scenario", r.input.scenario}, {"pairing", pairing_json(r)}});
    if (r.steps.steps() != 0 || r.steps.limited()) doc["scenarios"].back()["clock_steps"] = clock_steps_json(r);
  }
  return doc;
}

nlohmann::json stats_document(std::span<const analysis::ScenarioResult> results,
                              std::span<const analysis::TruthCheck> checks) {
  auto doc = stats_document(results);
  for (std::size_t k = 0; k < checks.size() && k < results.size(); ++k) {
    const auto& t = checks[k];
    doc["scenarios"][k]["truth"] = {{"true_pairs", t.true_pairs},
                                    {"found", t.found},
                                    {"correct", t.correct},
                                    {"wrong", t.wrong},
                                    {"wrong_not_ambiguous", t.wrong_clear},
                                    {"wrong_flagged", t.wrong_flagged},
                                    {"wrong_unflagged", t.wrong_unflagged},
                                    {"found_pct", t.found_percent()},
                                    {"passes", t.passes()},
                                    {"ambiguous", t.ambiguous},
                                    {"missed", t.missed},
                                    {"true_median_ms", t.true_median_ms},
                                    {"max_abs_error_ns", t.max_abs_error_ns},
                                    {"mean_error_ns", t.mean_error_ns}};
    if (t.with_uncertainty > 0)
      doc["scenarios"][k]["truth"]["uncertainty"] = {{"pairs", t.with_uncertainty},
                                                     {"coverage_u", number(t.coverage_u())},
                                                     {"coverage_U95", number(t.coverage_U95())},
                                                     {"coverage_max_error", number(t.coverage_max())},
                                                     {"median_U95_ns", number(t.median_U95_ns)},
                                                     {"median_abs_error_ns", number(t.median_abs_error_ns)},
                                                     {"width_ratio", number(t.width_ratio())}};
  }
  return doc;
}

}  // namespace m2mlat::report
