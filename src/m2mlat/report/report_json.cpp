// m2mlat-report/1. NaN (undefined) becomes null, like m2mlat-stats/1.
#include "m2mlat/report/report_json.hpp"

#include <cmath>

#include "m2mlat/report/comparison_text.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/formats/json_number.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/report/scenario_json.hpp"

namespace m2mlat::report {

using formats::number;

namespace {
// An undefined interval (NaN bounds) as null, not [null, null].
nlohmann::json interval_or_null(const stats::Interval& i) {
  if (std::isnan(i.lower)) return nullptr;
  return nlohmann::json::array({i.lower, i.upper});
}
}  // namespace

nlohmann::json comparison_json(const ComparisonReport& r) {
  const auto& c = r.comparison;
  nlohmann::json above = nlohmann::json::array();
  for (const auto& d : c.shares)
    above.push_back({{"threshold_ns", d.threshold.count()},
                     {"count_subject", d.count_subject},
                     {"count_baseline", d.count_baseline},
                     {"share_subject", number(d.share_subject)},
                     {"share_baseline", number(d.share_baseline)},
                     {"difference", number(d.difference)},
                     {"ci", interval_or_null(d.ci)}});
  return {{"subject", r.subject},
          {"baseline", r.baseline},
          {"n_subject", c.n_subject},
          {"n_baseline", c.n_baseline},
          {"median_subject_ms", number(c.median_subject_ms)},
          {"median_baseline_ms", number(c.median_baseline_ms)},
          {"iqr_subject_ms", number(c.iqr_subject_ms)},
          {"iqr_baseline_ms", number(c.iqr_baseline_ms)},
          {"sd_subject_ms", number(c.sd_subject_ms)},
          {"sd_baseline_ms", number(c.sd_baseline_ms)},
          {"median_difference_ms", number(c.median_difference_ms)},
          {"median_difference_ci_ms", interval_or_null(c.median_difference_ci_ms)},
          {"iqr_ratio", number(c.iqr_ratio)},
          {"iqr_ratio_ci", interval_or_null(c.iqr_ratio_ci)},
          {"sd_ratio", number(c.sd_ratio)},
          {"sd_ratio_ci", interval_or_null(c.sd_ratio_ci)},
          {"mann_whitney",
           {{"u_subject", c.mann_whitney.u_a},
            {"z", c.mann_whitney.z},
            {"p", c.mann_whitney.p},
            {"probability_subject_greater", number(c.mann_whitney.probability_a_greater)}}},
          {"brown_forsythe",
           {{"w", c.brown_forsythe.w},
            {"df1", c.brown_forsythe.df1},
            {"df2", c.brown_forsythe.df2},
            {"p", c.brown_forsythe.p}}},
          {"above", above},
          {"alpha", c.alpha},
          {"location_significant", c.location_significant()},
          {"spread_significant", c.spread_significant()},
          {"uncertainty_ms", number(c.uncertainty_ms)},
          {"median_difference_below_uncertainty", c.median_difference_below_uncertainty},
          {"iqr_difference_below_uncertainty", c.iqr_difference_below_uncertainty},
          {"bootstrap",
           {{"resamples", c.resamples},
            {"seed", c.seed},
            {"level", c.level},
            {"subject_resampled", resampling_name(c.subject_resampling)},
            {"baseline_resampled", resampling_name(c.baseline_resampling)}}},
          {"sentence", comparison_sentence(r)}};
}

nlohmann::json report_document(const Report& report) {
  nlohmann::json versions = nlohmann::json::object();
  for (const auto& [name, version] : report.versions) versions[name] = version;
  nlohmann::json doc{{"format", kReportFormat},
                     {"generated_by", {{"command", report.command}, {"versions", versions}}},
                     {"groups", report.groups},
                     {"alpha", report.alpha},
                     {"assumed_uncertainty_ms", number(report.assumed_uncertainty_ms)},
                     {"scenarios", nlohmann::json::array()},
                     {"comparisons", nlohmann::json::array()}};
  for (const auto& s : report.scenarios) {
    auto j = scenario_json(s.result);
    j["group"] = s.group.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.group);
    std::size_t known = 0;
    for (const auto& u : s.uncertainty_ns) known += u ? 1 : 0;
    j["uncertainty"] = {{"pairs_with_bound", known},
                        {"median_ms", number(s.median_uncertainty_ms())},  // U95 (k = 2)
                        {"max_ms", number(s.max_uncertainty_ms())},
                        {"median_max_error_ms", number(s.median_bound_ms())},
                        {"cause_clock_median_ms", number(s.result.cause_clock_ms)},
                        {"effect_clock_median_ms", number(s.result.effect_clock_ms)}};
    auto& clocks = j["clocks"] = nlohmann::json::array();
    for (const auto& c : s.result.clocks)
      clocks.push_back({{"node", c.node}, {"source", c.source}, {"samples", c.t_ns.size()}});
    auto& losses = j["losses"] = nlohmann::json::array();
    for (const auto& l : s.result.losses)
      losses.push_back({{"node", l.node}, {"kind", l.kind}, {"records", l.records}, {"events", l.events}});
    doc["scenarios"].push_back(std::move(j));
  }
  for (const auto& c : report.comparisons) doc["comparisons"].push_back(comparison_json(c));
  if (!report.full_loops.empty()) doc["full_loop"] = full_loop_json(report.full_loops);
  return doc;
}

}  // namespace m2mlat::report
