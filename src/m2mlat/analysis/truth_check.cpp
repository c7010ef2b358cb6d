// Matched pairs against true pairs, by (cause index, effect index).
#include "m2mlat/analysis/truth_check.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>

#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

double TruthCheck::found_percent() const {
  return true_pairs > 0 ? 100.0 * static_cast<double>(correct) / static_cast<double>(true_pairs) : 100.0;
}

bool TruthCheck::passes() const {
  // In integers: no rounding at the boundary.
  return wrong_unflagged == 0 && correct * 100 >= true_pairs * kMinFoundPercent;
}

std::vector<CoveragePoint> coverage_points(const ScenarioResult& result,
                                           const std::vector<sim::TruePair>& pairs) {
  std::vector<CoveragePoint> points;
  if (result.uncertainty.size() != result.match.pairs.size()) return points;
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> error_of;  // measured - true latency, ns
  for (const auto& t : pairs)
    error_of[{t.cause_index, t.effect_index}] = t.measured_latency.count() - t.true_latency.count();
  for (std::size_t i = 0; i < result.match.pairs.size(); ++i) {
    const auto& p = result.match.pairs[i];
    const auto it = error_of.find({p.cause_index, p.effect_index});
    if (it == error_of.end() || !result.uncertainty[i].bounded()) continue;
    points.push_back({std::llabs(it->second), result.uncertainty[i]});
  }
  return points;
}

namespace {

// The coverage figures of TruthCheck (see there).
void check_uncertainty(TruthCheck& check, const ScenarioResult& result,
                       const std::vector<sim::TruePair>& pairs) {
  std::vector<std::int64_t> widths, errors;
  for (const auto& [error, u] : coverage_points(result, pairs)) {
    ++check.with_uncertainty;
    check.within_u += error <= u.u_ns;
    check.within_U95 += error <= u.expanded_ns();
    check.within_max += error <= u.max_error_ns;
    widths.push_back(u.expanded_ns());
    errors.push_back(error);
  }
  if (widths.empty()) return;
  check.median_U95_ns = stats::median(std::move(widths));
  check.median_abs_error_ns = stats::median(std::move(errors));
}

}  // namespace

double TruthCheck::share(std::int64_t k) const {
  return with_uncertainty == 0 ? std::numeric_limits<double>::quiet_NaN()
                               : static_cast<double>(k) / static_cast<double>(with_uncertainty);
}

double TruthCheck::width_ratio() const {
  if (with_uncertainty == 0) return std::numeric_limits<double>::quiet_NaN();
  return median_abs_error_ns > 0 ? median_U95_ns / median_abs_error_ns
                                 : std::numeric_limits<double>::infinity();
}

std::vector<sim::TruePair> in_columns(std::vector<sim::TruePair> pairs,
                                      std::span<const std::int64_t> cause_stamps,
                                      std::span<const std::int64_t> effect_stamps,
                                      const ScenarioInput& input) {
  const auto position = [](std::int64_t index, std::span<const std::int64_t> stamps,
                           const store::Timestamps& column) {
    if (index < 0 || static_cast<std::size_t>(index) >= stamps.size()) return std::int64_t{-1};
    const std::int64_t stamp = stamps[static_cast<std::size_t>(index)];
    const auto it = std::lower_bound(column.t_ns.begin(), column.t_ns.end(), stamp);
    return it != column.t_ns.end() && *it == stamp ? static_cast<std::int64_t>(it - column.t_ns.begin())
                                                   : std::int64_t{-1};
  };
  for (auto& p : pairs) {
    p.cause_index = position(p.cause_index, cause_stamps, input.cause);
    p.effect_index = position(p.effect_index, effect_stamps, input.effect);
  }
  return pairs;
}

TruthCheck check_against_truth(const ScenarioResult& result,
                               const std::vector<sim::TruePair>& pairs) {
  TruthCheck check;
  check.true_pairs = static_cast<std::int64_t>(pairs.size());
  check.found = static_cast<std::int64_t>(result.match.pairs.size());
  std::set<std::pair<std::int64_t, std::int64_t>> found, truth;
  for (const auto& p : result.match.pairs) found.emplace(p.cause_index, p.effect_index);
  for (const auto& t : pairs) truth.emplace(t.cause_index, t.effect_index);
  for (const auto& p : result.match.pairs) {
    check.ambiguous += p.ambiguous();
    if (truth.contains({p.cause_index, p.effect_index})) continue;
    check.wrong_clear += !p.ambiguous();
    (p.flags != 0 ? check.wrong_flagged : check.wrong_unflagged) += 1;
  }

  std::vector<std::int64_t> true_latencies;
  double error_sum = 0;
  for (const auto& t : pairs) {
    true_latencies.push_back(t.true_latency.count());
    if (!found.contains({t.cause_index, t.effect_index})) continue;
    ++check.correct;
    const std::int64_t error = t.measured_latency.count() - t.true_latency.count();
    check.max_abs_error_ns = std::max(check.max_abs_error_ns, error < 0 ? -error : error);
    error_sum += static_cast<double>(error);
  }
  check.wrong = check.found - check.correct;
  check.missed = check.true_pairs - check.correct;
  check.mean_error_ns = check.correct > 0 ? error_sum / static_cast<double>(check.correct) : 0.0;
  std::sort(true_latencies.begin(), true_latencies.end());
  check.true_median_ms = true_latencies.empty() ? 0.0 : stats::quantile(true_latencies, 0.5) / 1e6;
  check_uncertainty(check, result, pairs);
  return check;
}

}  // namespace m2mlat::analysis
