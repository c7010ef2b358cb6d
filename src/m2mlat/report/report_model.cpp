// Gathering a report's data: clock state and losses from the store, groups, comparisons.
#include "m2mlat/report/report_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "m2mlat/core/error.hpp"
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

std::optional<double> ScenarioReport::median_uncertainty_ms() const {
  std::vector<std::int64_t> v;
  for (std::size_t i = 0; i < uncertainty_ns.size(); ++i)
    if (uncertainty_ns[i] && (result.include_ambiguous || !result.match.pairs[i].ambiguous()))
      v.push_back(*uncertainty_ns[i]);
  return median_ms(std::move(v));
}

std::optional<double> ScenarioReport::max_uncertainty_ms() const {
  std::optional<std::int64_t> m;
  for (std::size_t i = 0; i < uncertainty_ns.size(); ++i)
    if (uncertainty_ns[i] && (result.include_ambiguous || !result.match.pairs[i].ambiguous()))
      m = std::max(m.value_or(0), *uncertainty_ns[i]);
  if (!m) return std::nullopt;
  return static_cast<double>(*m) / 1e6;
}

const ScenarioReport* Report::find(const std::string& scenario) const {
  for (const auto& s : scenarios)
    if (s.result.input.scenario == scenario) return &s;
  return nullptr;
}

std::optional<std::int64_t> clock_bound_at(const ClockSeries& series, std::int64_t t_ns) {
  if (series.t_ns.empty()) return std::nullopt;
  auto it = std::upper_bound(series.t_ns.begin(), series.t_ns.end(), t_ns);
  const auto k = it == series.t_ns.begin() ? 0 : static_cast<std::size_t>(it - series.t_ns.begin()) - 1;
  return series.max_error_ns[k];
}

void attach_store_data(ScenarioReport& s, const store::Store& store) {
  const auto& in = s.result.input;
  std::map<std::string, ClockSeries> by_node;
  std::map<std::pair<std::string, std::string>, LossCount> losses;
  for (const auto& session : store.sessions()) {
    if (session.scenario != in.scenario) continue;
    if (session.node != in.cause_ref.node && session.node != in.effect_ref.node) continue;
    auto& series = by_node[session.node];
    series.node = session.node;
    for (const auto& c : store.clock_samples(session.id)) {
      if (c.time.clock() != in.clock) continue;
      if (series.source.empty()) series.source = c.source;
      series.t_ns.push_back(c.time.ns());
      series.offset_ns.push_back(c.offset_ns);
      series.max_error_ns.push_back(c.max_error_ns);
    }
    for (const auto& l : store.losses(session.id)) {
      auto& count = losses[{session.node, l.kind}];
      count.node = session.node;
      count.kind = l.kind;
      ++count.records;
      count.events += l.count;
    }
  }
  for (auto& entry : by_node) {
    const auto& series = entry.second;  // a named reference: clang 14 cannot capture structured bindings
    // Sessions of one node follow each other; keep the samples in time order.
    std::vector<std::size_t> order(series.t_ns.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return series.t_ns[a] < series.t_ns[b]; });
    ClockSeries sorted{series.node, series.source, {}, {}, {}};
    for (auto i : order) {
      sorted.t_ns.push_back(series.t_ns[i]);
      sorted.offset_ns.push_back(series.offset_ns[i]);
      sorted.max_error_ns.push_back(series.max_error_ns[i]);
    }
    if (!sorted.t_ns.empty()) s.clocks.push_back(std::move(sorted));
  }
  for (auto& [key, count] : losses) s.losses.push_back(count);

  const ClockSeries* cause = nullptr;
  const ClockSeries* effect = nullptr;
  for (const auto& c : s.clocks) {
    if (c.node == in.cause_ref.node) cause = &c;
    if (c.node == in.effect_ref.node) effect = &c;
  }
  s.uncertainty_ns.assign(s.result.match.pairs.size(), std::nullopt);
  if (!cause || !effect) return;
  std::vector<std::int64_t> cause_bounds, effect_bounds;
  for (std::size_t i = 0; i < s.result.match.pairs.size(); ++i) {
    const auto& p = s.result.match.pairs[i];
    const auto bc = clock_bound_at(*cause, p.cause_time.ns());
    const auto be = clock_bound_at(*effect, p.effect_time.ns());
    s.uncertainty_ns[i] = *bc + *be;
    // The analysis' own per-sample bound (neighbouring samples, kernel term) when it made one.
    if (i < s.result.uncertainty.size())
      s.uncertainty_ns[i] = s.result.uncertainty[i].bounded()
                                ? std::optional(s.result.uncertainty[i].max_error_ns)
                                : std::nullopt;
    if (s.result.include_ambiguous || !p.ambiguous()) {
      cause_bounds.push_back(*bc);
      effect_bounds.push_back(*be);
    }
  }
  s.cause_clock_ms = median_ms(std::move(cause_bounds));
  s.effect_clock_ms = median_ms(std::move(effect_bounds));
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

std::vector<std::pair<std::string, std::string>> default_comparisons(const Report& report) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto& sc = report.scenarios;
  for (std::size_t j = 0; j < sc.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (sc[i].group == sc[j].group)
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
    r.comparison = stats::compare(s->result.latencies_ns(), b->result.latencies_ns(), options);
  } catch (const core::Error& e) {
    throw core::Error(e.kind(), fmt::format("{} vs {}: {}", subject, baseline, e.what()));
  }
  return r;
}

}  // namespace m2mlat::report
