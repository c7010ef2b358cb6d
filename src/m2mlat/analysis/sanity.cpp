// The sanity verdict of an analysed scenario (rules in sanity.hpp).
#include "m2mlat/analysis/sanity.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

namespace {

// Pairs, median and IQR of the unflagged pairs of the first edges of two sides, ms.
struct Direction {
  std::size_t pairs = 0;
  double median_ms = 0, iqr_ms = 0;
};

Direction pair_window(std::span<const std::int64_t> cause, std::span<const std::int64_t> effect, core::Clock clock,
                      const pairing::MatchOptions& options) {
  std::vector<std::int64_t> c(cause.begin(), cause.begin() + static_cast<std::ptrdiff_t>(std::min(cause.size(), kSanityWindow)));
  std::vector<std::int64_t> e;
  if (!c.empty()) {
    const std::int64_t end = c.back() + options.max_latency.count();
    for (std::size_t k = 0; k < effect.size() && e.size() < 2 * kSanityWindow && effect[k] <= end; ++k)
      if (effect[k] >= c.front() + options.min_latency.count()) e.push_back(effect[k]);
  }
  const auto m = pairing::match_in_place(c, e, clock, options);
  std::vector<double> ms;
  for (const auto& p : m.pairs)
    if (p.flags == 0) ms.push_back(static_cast<double>(e[p.effect_index] - c[p.cause_index]) / 1e6);
  Direction d;
  d.pairs = ms.size();
  if (ms.size() < 4) return d;
  std::sort(ms.begin(), ms.end());
  d.median_ms = stats::quantile(ms, 0.5);
  d.iqr_ms = stats::quantile(ms, 0.75) - stats::quantile(ms, 0.25);
  return d;
}

}  // namespace

std::vector<SanityWarning> sanity_warnings(const ScenarioResult& result, const pairing::MatchOptions& options) {
  std::vector<SanityWarning> out;
  const auto& in = result.input;
  if (in.cause.t_ns.empty() || in.effect.t_ns.empty()) return out;
  if (result.match.pairs.empty()) {
    out.push_back({"no_pairs", fmt::format("no {} edge pairs with a {} edge within {:g} .. {:g} s", core::to_string(in.cause_ref),
                                           core::to_string(in.effect_ref), static_cast<double>(options.min_latency.count()) / 1e9,
                                           static_cast<double>(options.max_latency.count()) / 1e9)});
    return out;
  }
  const auto given = pair_window(in.cause.t_ns, in.effect.t_ns, in.clock, options);
  const auto reversed = pair_window(in.effect.t_ns, in.cause.t_ns, in.clock, options);
  const bool kept = reversed.pairs >= 4 && 5 * reversed.pairs >= 4 * given.pairs;
  const bool steadier = kept && 2 * reversed.iqr_ms < given.iqr_ms;
  // The effect side leads at both ends of the recording, each by less than a latency window.
  const auto& c = in.cause.t_ns;
  const auto& e = in.effect.t_ns;
  const std::int64_t window = options.max_latency.count();
  const bool leads = e.front() < c.front() && c.front() - e.front() <= window && e.back() < c.back() &&
                     c.back() - e.back() <= window;
  if (steadier || (kept && leads) || (given.pairs >= 4 && given.median_ms < 0))
    out.push_back({"roles_swapped",
                   fmt::format("cause and effect look swapped{}: over the first {} edges, {} -> {} gives {} pairs, "
                               "median {:.1f} ms, IQR {:.1f} ms; reversed ({} -> {}) {} pairs, median {:.1f} ms, "
                               "IQR {:.1f} ms (check --cause/--effect, the roles given at import, or the files' order)",
                               leads ? " (the effect's edges come first at the start and last at the end)" : "",
                               std::min(in.cause.t_ns.size(), kSanityWindow), core::to_string(in.cause_ref),
                               core::to_string(in.effect_ref), given.pairs, given.median_ms, given.iqr_ms,
                               core::to_string(in.effect_ref), core::to_string(in.cause_ref), reversed.pairs,
                               reversed.median_ms, reversed.iqr_ms)});
  return out;
}

}  // namespace m2mlat::analysis
