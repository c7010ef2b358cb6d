// Matched pairs against true pairs, by (cause index, effect index).
#include "m2mlat/analysis/truth_check.hpp"

#include <algorithm>
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
  return check;
}

}  // namespace m2mlat::analysis
