// A report's model: per-pair bounds from the analysis, groups, comparisons.
#include "m2mlat/report/report_model.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/nearest.hpp"
#include "m2mlat/report/scenario_colours.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::report {

namespace {
std::optional<double> median_ms(std::vector<std::int64_t> v) {
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  return stats::quantile(std::span<const std::int64_t>(v), 0.5) / 1e6;
}

std::string prefix_of(const std::string& name) {
  const auto cut = name.find_first_of("_-");
  return cut == std::string::npos || cut == 0 ? name : name.substr(0, cut);
}
}  // namespace

std::vector<std::int64_t> ScenarioReport::known_in_statistics(
    const std::vector<std::optional<std::int64_t>>& values) const {
  std::vector<std::int64_t> v;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i] && (result.include_ambiguous || !result.match.pairs[i].ambiguous()))
      v.push_back(*values[i]);
  return v;
}

std::optional<double> ScenarioReport::median_uncertainty_ms() const {
  return median_ms(known_in_statistics(uncertainty_ns));
}

std::optional<double> ScenarioReport::max_uncertainty_ms() const {
  const auto v = known_in_statistics(uncertainty_ns);
  if (v.empty()) return std::nullopt;
  return static_cast<double>(*std::max_element(v.begin(), v.end())) / 1e6;
}

std::optional<double> ScenarioReport::median_bound_ms() const {
  return median_ms(known_in_statistics(max_error_ns));
}

const ScenarioReport* Report::find(const std::string& scenario) const {
  for (const auto& s : scenarios)
    if (s.result.input.scenario == scenario) return &s;
  return nullptr;
}

ScenarioReport scenario_report(analysis::ScenarioResult result) {
  ScenarioReport s{std::move(result), {}, {}, {}};
  const auto& u = s.result.uncertainty;
  s.uncertainty_ns.reserve(s.result.match.pairs.size());
  s.max_error_ns.reserve(s.result.match.pairs.size());
  for (std::size_t i = 0; i < s.result.match.pairs.size(); ++i) {
    const bool bounded = i < u.size() && u[i].bounded();
    s.uncertainty_ns.push_back(bounded ? std::optional(u[i].expanded_ns()) : std::nullopt);
    s.max_error_ns.push_back(bounded ? std::optional(u[i].max_error_ns) : std::nullopt);
  }
  return s;
}

void assign_groups(Report& report,
                   const std::vector<std::pair<std::string, std::vector<std::string>>>& explicit_groups,
                   bool by_prefix) {
  report.groups.clear();
  for (auto& s : report.scenarios) s.group.clear();
  if (!explicit_groups.empty()) {
    for (const auto& [name, members] : explicit_groups) {
      for (const auto& m : members) {
        bool found = false;
        for (auto& s : report.scenarios)
          if (s.result.input.scenario == m) s.group = name, found = true;
        if (!found)
          throw core::Error(core::ErrorKind::usage,
                            fmt::format("--group {}: no scenario '{}' in the inputs", name, m));
      }
      report.groups.push_back(name);
    }
    // Scenarios not named in any group form one more group, "other".
    for (auto& s : report.scenarios)
      if (s.group.empty()) {
        s.group = "other";
        if (std::find(report.groups.begin(), report.groups.end(), "other") == report.groups.end())
          report.groups.push_back("other");
      }
    return;
  }
  if (!by_prefix) return;
  std::vector<std::string> groups;
  for (const auto& s : report.scenarios) {
    const auto g = prefix_of(s.result.input.scenario);
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  if (groups.size() == report.scenarios.size()) return;  // every scenario alone: no grouping
  report.groups = groups;
  for (auto& s : report.scenarios) s.group = prefix_of(s.result.input.scenario);
}

std::vector<std::pair<std::string, std::string>> default_comparisons(const Report& report,
                                                                     const std::string& baseline) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto& sc = report.scenarios;
  const ScenarioReport* base = nullptr;
  if (!baseline.empty()) {
    base = report.find(baseline);
    if (base == nullptr) {
      std::vector<std::string> names;
      for (const auto& s : sc) names.push_back(s.result.input.scenario);
      throw core::Error(core::ErrorKind::usage, fmt::format("--baseline: no scenario '{}'{}", baseline,
                                                            core::did_you_mean(baseline, names)));
    }
    for (const auto& s : sc)
      if (&s != base && s.group == base->group) out.emplace_back(s.result.input.scenario, baseline);
  }
  for (std::size_t j = 0; j < sc.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (sc[i].group == sc[j].group && (base == nullptr || sc[i].group != base->group))
        out.emplace_back(sc[j].result.input.scenario, sc[i].result.input.scenario);
  return out;
}

ComparisonReport compare_scenarios(const Report& report, const std::string& subject,
                                   const std::string& baseline, stats::CompareOptions options) {
  const auto* s = report.find(subject);
  const auto* b = report.find(baseline);
  for (const auto& [name, found] : {std::pair{subject, s}, std::pair{baseline, b}})
    if (!found) throw core::Error(core::ErrorKind::usage, fmt::format("--compare: no scenario '{}'", name));
  const auto us = s->median_uncertainty_ms(), ub = b->median_uncertainty_ms();
  if (us || ub)
    options.uncertainty_ms = std::max(us.value_or(0.0), ub.value_or(0.0));
  else
    options.uncertainty_ms = report.assumed_uncertainty_ms;
  options.alpha = report.alpha;
  ComparisonReport r{subject, baseline, {}};
  try {
    const auto subject_ns = s->result.latencies_ns(), baseline_ns = b->result.latencies_ns();
    const auto subject_units = s->result.manoeuvre_starts(), baseline_units = b->result.manoeuvre_starts();
    r.comparison = stats::compare({subject_ns, true, subject_units}, {baseline_ns, true, baseline_units}, options);
  } catch (const core::Error& e) {
    throw core::Error(e.kind(), fmt::format("{} vs {}: {}", subject, baseline, e.what()));
  }
  return r;
}

std::vector<std::size_t> Report::colours() const {
  std::vector<std::string> names;
  for (const auto& s : scenarios) names.push_back(s.result.input.scenario);
  return scenario_colours(names);
}

std::size_t Report::colour(const std::string& scenario) const {
  const auto all = colours();
  for (std::size_t i = 0; i < scenarios.size(); ++i)
    if (scenarios[i].result.input.scenario == scenario) return all[i];
  return 0;
}

const analysis::FullLoopResult* Report::find_full_loop(const std::string& scenario) const {
  for (const auto& r : full_loops)
    if (r.scenario == scenario) return &r;
  return nullptr;
}

std::vector<ComparisonReport> compare_full_loops(const Report& report, const std::string& subject,
                                                 const std::string& baseline, stats::CompareOptions options) {
  const auto* s = report.find_full_loop(subject);
  const auto* b = report.find_full_loop(baseline);
  for (const auto& [name, found] : {std::pair{subject, s}, std::pair{baseline, b}})
    if (!found)
      throw core::Error(core::ErrorKind::usage, fmt::format("--compare: no full-loop file '{}'", name));
  options.uncertainty_ms = report.assumed_uncertainty_ms;
  options.alpha = report.alpha;
  std::vector<ComparisonReport> out;
  for (const auto q :
       {analysis::LoopQuantity::m2m, analysis::LoopQuantity::g2g, analysis::LoopQuantity::e2e}) {
    const auto* sq = s->find(q);
    const auto* bq = b->find(q);
    if (sq == nullptr || bq == nullptr || sq->ns.size() < 2 || bq->ns.size() < 2) continue;
    ComparisonReport r{fmt::format("{} {}", subject, analysis::label(q)),
                       fmt::format("{} {}", baseline, analysis::label(q)),
                       {}};
    try {
      r.comparison = stats::compare(sq->ns, bq->ns, options);
    } catch (const core::Error& e) {
      throw core::Error(e.kind(), fmt::format("{} vs {}: {}", r.subject, r.baseline, e.what()));
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> default_full_loop_comparisons(const Report& report) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto& f = report.full_loops;
  for (std::size_t j = 0; j < f.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) out.emplace_back(f[j].scenario, f[i].scenario);
  return out;
}

}  // namespace m2mlat::report
