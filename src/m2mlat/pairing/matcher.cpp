// Order-preserving one-to-one alignment of cause and effect edges (see matcher.hpp for the method).
#include "m2mlat/pairing/matcher.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/pairing/refractory.hpp"

namespace m2mlat::pairing {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// The kept (non-bounce) edges of one side, as timestamps plus their input indices.
struct Kept {
  std::vector<std::int64_t> ns;
  std::vector<std::int64_t> input_index;
};

Kept kept_side(std::span<const std::int64_t> times, const RefractoryResult& filtered) {
  Kept side;
  side.ns.reserve(filtered.kept.size());
  side.input_index = filtered.kept;
  for (auto index : filtered.kept) side.ns.push_back(times[static_cast<std::size_t>(index)]);
  return side;
}

// For cause i, its candidate effects are [lo[i], hi[i]): those with latency in [min, max].
struct Windows {
  std::vector<std::uint32_t> lo, hi;
};

Windows latency_windows(const std::vector<std::int64_t>& causes, const std::vector<std::int64_t>& effects,
                        std::int64_t min_ns, std::int64_t max_ns) {
  Windows w;
  w.lo.resize(causes.size());
  w.hi.resize(causes.size());
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < causes.size(); ++i) {
    while (lo < effects.size() && effects[lo] - causes[i] < min_ns) ++lo;
    if (hi < lo) hi = lo;
    while (hi < effects.size() && effects[hi] - causes[i] <= max_ns) ++hi;
    w.lo[i] = static_cast<std::uint32_t>(lo);
    w.hi[i] = static_cast<std::uint32_t>(hi);
  }
  return w;
}

// Global reference latency: the centre of the densest 20 ms-wide bin of all candidate latencies.
// True pairs pile up around the typical latency; wrong candidates spread over the whole window.
std::int64_t global_reference(const std::vector<std::int64_t>& causes,
                              const std::vector<std::int64_t>& effects, const Windows& w, std::int64_t min_ns,
                              std::int64_t max_ns) {
  constexpr std::int64_t kBin = 20'000'000;  // ns
  std::vector<std::int64_t> counts(static_cast<std::size_t>((max_ns - min_ns) / kBin + 3), 0);
  for (std::size_t i = 0; i < causes.size(); ++i)
    for (auto j = w.lo[i]; j < w.hi[i]; ++j)
      ++counts[static_cast<std::size_t>((effects[j] - causes[i] - min_ns) / kBin) + 1];
  // Smooth over the neighbouring bins so that a spread-out peak wins over a lucky spike.
  std::size_t best_bin = 1;
  std::int64_t best_count = -1;
  for (std::size_t b = 1; b + 1 < counts.size(); ++b) {
    const std::int64_t smoothed = counts[b - 1] + 2 * counts[b] + counts[b + 1];
    if (smoothed > best_count) best_count = smoothed, best_bin = b;
  }
  return min_ns + static_cast<std::int64_t>(best_bin - 1) * kBin + kBin / 2;
}

// One alignment pass. reference(i) is the expected latency of cause i (ns). A candidate (i, j) is
// allowed if |latency - reference(i)| < tolerance and then fits by tolerance - |latency - reference(i)|.
// A chain's value is (pairs, total fit) compared lexicographically when `most_pairs_first`, else
// (total fit) alone. Returns for each cause the matched effect or kNone.
//
// G(i, j) = value(i, j) + max(0, max{ G(i', j') : i' < i, j' < j }) is the best value of an ordered
// chain of pairs ending in (i, j). Causes are processed in order; for effects we keep best[j] = max
// over the causes so far of G(., j). Because candidate windows only move forward, effects left behind
// by the window are folded into one `frozen` maximum, so each cause costs O(its window).
template <typename Reference>
std::vector<std::uint32_t> align(const std::vector<std::int64_t>& causes,
                                 const std::vector<std::int64_t>& effects, const Windows& w,
                                 std::int64_t tolerance_ns, bool most_pairs_first, Reference reference) {
  struct Best {                      // 16 bytes: one per effect
    std::int64_t fit = 0;             // sum of (tolerance - deviation), ns
    std::uint32_t pairs = 0;          // counted only when most_pairs_first (fewer than 2^32 causes)
    std::uint32_t candidate = kNone;  // the chain's last candidate, or kNone for the empty chain
    bool operator>(const Best& o) const { return pairs != o.pairs ? pairs > o.pairs : fit > o.fit; }
  };
  const std::uint32_t pair_count = most_pairs_first ? 1 : 0;
  // Candidates, in cause order: the effect index and the predecessor candidate (8 bytes each),
  // reserved for every window's size so that the vectors never grow past what is needed.
  std::vector<std::uint32_t> cand_effect, cand_pred;
  std::size_t window_total = 0;
  for (std::size_t i = 0; i < causes.size(); ++i) window_total += w.hi[i] - w.lo[i];
  cand_effect.reserve(window_total);
  cand_pred.reserve(window_total);
  std::vector<std::uint32_t> row_start(causes.size() + 1, 0);
  std::vector<Best> best(effects.size());
  Best frozen;  // best over effects [0, folded)
  std::size_t folded = 0;
  std::vector<std::pair<std::uint32_t, Best>> row;  // this cause's chain ends, applied after the row

  for (std::size_t i = 0; i < causes.size(); ++i) {
    row_start[i] = static_cast<std::uint32_t>(cand_effect.size());
    for (; folded < w.lo[i]; ++folded)
      if (best[folded] > frozen) frozen = best[folded];
    const std::int64_t ref = reference(i);
    Best running = frozen;  // max over effects < j, from causes < i
    row.clear();
    for (auto j = w.lo[i]; j < w.hi[i]; ++j) {
      const std::int64_t latency = effects[j] - causes[i];
      const std::int64_t deviation = latency > ref ? latency - ref : ref - latency;
      if (deviation < tolerance_ns) {
        if (cand_effect.size() >= kNone)
          throw core::Error(core::ErrorKind::usage, "too many candidate pairs: narrow the latency window");
        const auto id = static_cast<std::uint32_t>(cand_effect.size());
        cand_effect.push_back(j);
        cand_pred.push_back(running.candidate);
        row.emplace_back(j, Best{running.fit + (tolerance_ns - deviation), running.pairs + pair_count, id});
      }
      if (best[j] > running) running = best[j];
    }
    for (const auto& [j, chain] : row)
      if (chain > best[j]) best[j] = chain;
  }
  row_start[causes.size()] = static_cast<std::uint32_t>(cand_effect.size());

  Best overall = frozen;
  for (std::size_t j = folded; j < effects.size(); ++j)
    if (best[j] > overall) overall = best[j];

  // Walk the chain back; candidates are numbered in cause order, so the row pointer only moves down.
  std::vector<std::uint32_t> match(causes.size(), kNone);
  std::size_t i = causes.size();
  for (auto c = overall.candidate; c != kNone; c = cand_pred[c]) {
    while (row_start[i] > c) --i;
    match[i] = cand_effect[c];
  }
  return match;
}

// Running median of the matched latencies over `k` pairs either side, assigned to every cause (causes
// without a pass-1 pair take the value of the nearest pair before them, or the first pair).
std::vector<std::int64_t> local_reference(const std::vector<std::int64_t>& causes,
                                          const std::vector<std::int64_t>& effects,
                                          const std::vector<std::uint32_t>& match, int k,
                                          std::int64_t fallback) {
  std::vector<std::size_t> pair_cause;
  std::vector<std::int64_t> latency;
  for (std::size_t i = 0; i < causes.size(); ++i)
    if (match[i] != kNone) {
      pair_cause.push_back(i);
      latency.push_back(effects[match[i]] - causes[i]);
    }
  std::vector<std::int64_t> reference(causes.size(), fallback);
  if (latency.empty()) return reference;
  // The window [p - k, p + k] slides one pair at a time: keep it sorted, remove the pair that
  // leaves and insert the one that enters (binary search + a short move), instead of re-selecting.
  std::vector<std::int64_t> median(latency.size()), window;
  const auto n = static_cast<std::ptrdiff_t>(latency.size());
  std::ptrdiff_t first = 0, last = 0;  // the window holds latency[first, last)
  for (std::ptrdiff_t p = 0; p < n; ++p) {
    const auto want_first = std::max<std::ptrdiff_t>(0, p - k), want_last = std::min<std::ptrdiff_t>(n, p + k + 1);
    for (; last < want_last; ++last) {
      const auto value = latency[static_cast<std::size_t>(last)];
      window.insert(std::upper_bound(window.begin(), window.end(), value), value);
    }
    for (; first < want_first; ++first)
      window.erase(std::lower_bound(window.begin(), window.end(), latency[static_cast<std::size_t>(first)]));
    median[static_cast<std::size_t>(p)] = window[window.size() / 2];
  }
  std::size_t p = 0;
  for (std::size_t i = 0; i < causes.size(); ++i) {
    while (p + 1 < pair_cause.size() && pair_cause[p + 1] <= i) ++p;
    reference[i] = median[p];
  }
  return reference;
}

// Bursts: runs of kept edges on one side closer than `gap` to the previous one. Returns the burst
// number of every edge.
std::vector<std::uint32_t> bursts(const std::vector<std::int64_t>& times, std::int64_t gap_ns) {
  std::vector<std::uint32_t> id(times.size(), 0);
  for (std::size_t k = 1; k < times.size(); ++k)
    id[k] = id[k - 1] + (times[k] - times[k - 1] >= gap_ns ? 1 : 0);
  return id;
}

// Marks the pairs whose assignment the data cannot make certain (PairFlag kPairAmbiguous):
//  - a burst on either side holds an edge without partner (a pass missed on one side, or an extra
//    edge): the order-preserving rule then had a choice of which edges to leave out;
//  - a burst on one side is paired with edges of two bursts on the other side;
//  - within a burst, the effect edges' spacing does not follow the cause edges' spacing: for two
//    consecutive pairs in one burst, (effect interval / cause interval) differs from the median of
//    that ratio over all bursts by more than a factor kPatternFactor. The vehicle's wheel replays the
//    operator's motion at a similar speed, so both sides show the same pattern of magnet passes;
//    passes missed on BOTH sides at different magnets leave the counts equal but break the pattern.
std::vector<bool> ambiguous_pairs(const std::vector<std::int64_t>& causes,
                                  const std::vector<std::int64_t>& effects,
                                  const std::vector<std::uint32_t>& matched, std::int64_t gap_ns) {
  constexpr double kPatternFactor = 1.5;
  const auto cause_burst = bursts(causes, gap_ns), effect_burst = bursts(effects, gap_ns);
  const std::size_t n_cause_bursts = causes.empty() ? 0 : cause_burst.back() + 1;
  const std::size_t n_effect_bursts = effects.empty() ? 0 : effect_burst.back() + 1;
  std::vector<bool> cause_bad(n_cause_bursts, false), effect_bad(n_effect_bursts, false);
  std::vector<bool> effect_used(effects.size(), false);
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] == kNone)
      cause_bad[cause_burst[i]] = true;
    else
      effect_used[matched[i]] = true;
  }
  for (std::size_t j = 0; j < effects.size(); ++j)
    if (!effect_used[j]) effect_bad[effect_burst[j]] = true;
  // One burst of passes on one side must map to one burst on the other: pairs joining a cause burst
  // to two effect bursts (or the reverse) mean an edge was taken from a neighbouring manoeuvre.
  {
    std::vector<std::uint32_t> effect_of(n_cause_bursts, kNone), cause_of(n_effect_bursts, kNone);
    for (std::size_t i = 0; i < matched.size(); ++i) {
      if (matched[i] == kNone) continue;
      const auto cb = cause_burst[i], eb = effect_burst[matched[i]];
      if (effect_of[cb] == kNone) effect_of[cb] = eb;
      if (cause_of[eb] == kNone) cause_of[eb] = cb;
      if (effect_of[cb] != eb || cause_of[eb] != cb) {
        cause_bad[cb] = cause_bad[cause_of[eb]] = true;
        effect_bad[eb] = effect_bad[effect_of[cb]] = true;
      }
    }
  }

  // Interval ratios of consecutive pairs sharing a burst on both sides.
  struct Step {
    std::uint32_t cause_burst, effect_burst;
    double ratio;
  };
  std::vector<Step> steps;
  std::size_t prev = kNone;
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] == kNone) continue;
    if (prev != kNone && cause_burst[prev] == cause_burst[i] &&
        effect_burst[matched[prev]] == effect_burst[matched[i]])
      steps.push_back({cause_burst[i], effect_burst[matched[i]],
                       static_cast<double>(effects[matched[i]] - effects[matched[prev]]) /
                           static_cast<double>(causes[i] - causes[prev])});
    prev = i;
  }
  if (!steps.empty()) {
    std::vector<double> ratios;
    for (const auto& s : steps) ratios.push_back(s.ratio);
    auto mid = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
    std::nth_element(ratios.begin(), mid, ratios.end());
    const double median = *mid;
    for (const auto& s : steps)
      if (s.ratio > median * kPatternFactor || s.ratio < median / kPatternFactor)
        cause_bad[s.cause_burst] = effect_bad[s.effect_burst] = true;
  }

  std::vector<bool> ambiguous(matched.size(), false);
  for (std::size_t i = 0; i < matched.size(); ++i)
    if (matched[i] != kNone) ambiguous[i] = cause_bad[cause_burst[i]] || effect_bad[effect_burst[matched[i]]];
  return ambiguous;
}

void check_sorted(std::span<const std::int64_t> times, const char* side) {
  const auto it = std::is_sorted_until(times.begin(), times.end());
  if (it != times.end())
    throw core::Error(core::ErrorKind::data, fmt::format("{} timestamps are not in time order (at index {})",
                                                         side, it - times.begin()));
}

}  // namespace

MatchResult match(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                  core::Clock clock, const MatchOptions& options) {
  if (options.max_latency <= options.min_latency)
    throw core::Error(core::ErrorKind::usage,
                      "the latency window is empty: max latency must exceed min latency");
  if (options.tolerance.count() <= 0)
    throw core::Error(core::ErrorKind::usage, "the tolerance must be positive");
  if (options.reference_neighbours < 1)
    throw core::Error(core::ErrorKind::usage, "reference neighbours must be >= 1");
  if (cause_ns.size() >= kNone || effect_ns.size() >= kNone)
    throw core::Error(core::ErrorKind::usage, "more than 4 billion events on one side: split the input");
  check_sorted(cause_ns, "cause");
  check_sorted(effect_ns, "effect");

  const auto cause_filter = refractory_filter(cause_ns, options.refractory);
  const auto effect_filter = refractory_filter(effect_ns, options.refractory);
  const Kept causes = kept_side(cause_ns, cause_filter);
  const Kept effects = kept_side(effect_ns, effect_filter);
  const std::int64_t min_ns = options.min_latency.count(), max_ns = options.max_latency.count();
  const Windows windows = latency_windows(causes.ns, effects.ns, min_ns, max_ns);

  // Pass 1: one global reference; every candidate in the window is allowed, and the best fit wins
  // (not the most pairs, so a missing edge cannot shift a chain of pairs to gain one).
  const std::int64_t global = global_reference(causes.ns, effects.ns, windows, min_ns, max_ns);
  const std::int64_t wide = (max_ns - min_ns) + 1;
  auto match1 = align(causes.ns, effects.ns, windows, wide, false, [&](std::size_t) { return global; });
  // Pass 2: the local reference; within the tolerance, the most pairs, then the best fit.
  auto reference = local_reference(causes.ns, effects.ns, match1, options.reference_neighbours, global);
  match1 = {};
  const auto matched = align(causes.ns, effects.ns, windows, options.tolerance.count(), true,
                             [&](std::size_t i) { return reference[i]; });
  reference = {};

  MatchResult result;
  result.clock = clock;
  result.cause_count = static_cast<std::int64_t>(cause_ns.size());
  result.effect_count = static_cast<std::int64_t>(effect_ns.size());
  std::vector<bool> effect_used(effects.ns.size(), false);
  const auto ambiguous = ambiguous_pairs(causes.ns, effects.ns, matched, options.burst_gap.count());
  result.pairs.reserve(static_cast<std::size_t>(
      std::count_if(matched.begin(), matched.end(), [](std::uint32_t j) { return j != kNone; })));
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] == kNone) continue;
    const auto j = matched[i];
    effect_used[j] = true;
    result.pairs.push_back(
        Pair{causes.input_index[i], effects.input_index[j], core::TimePoint::from_ns(clock, causes.ns[i]),
             core::TimePoint::from_ns(clock, effects.ns[j]), ambiguous[i] ? kPairAmbiguous : 0u});
  }

  // Reasons for everything left over, in input order per side.
  auto add = [&](Side side, std::int64_t index, std::span<const std::int64_t> times, UnmatchedReason reason) {
    result.unmatched.push_back(Unmatched{
        side, index, core::TimePoint::from_ns(clock, times[static_cast<std::size_t>(index)]), reason});
  };
  for (std::size_t i = 0; i < matched.size(); ++i)
    if (matched[i] == kNone)
      add(Side::cause, causes.input_index[i], cause_ns,
          windows.lo[i] == windows.hi[i] ? UnmatchedReason::no_candidate : UnmatchedReason::outmatched);
  for (auto index : cause_filter.bounces) add(Side::cause, index, cause_ns, UnmatchedReason::bounce);
  for (std::size_t j = 0; j < effects.ns.size(); ++j) {
    if (effect_used[j]) continue;
    // A cause in [effect - max, effect - min] would have had this effect as a candidate.
    const auto first = std::lower_bound(causes.ns.begin(), causes.ns.end(), effects.ns[j] - max_ns);
    const bool candidate = first != causes.ns.end() && *first <= effects.ns[j] - min_ns;
    add(Side::effect, effects.input_index[j], effect_ns,
        candidate ? UnmatchedReason::outmatched : UnmatchedReason::no_candidate);
  }
  for (auto index : effect_filter.bounces) add(Side::effect, index, effect_ns, UnmatchedReason::bounce);
  std::sort(result.unmatched.begin(), result.unmatched.end(), [](const Unmatched& a, const Unmatched& b) {
    return a.side != b.side ? a.side < b.side : a.index < b.index;
  });
  return result;
}

MatchResult match(std::span<const core::Event> causes, std::span<const core::Event> effects,
                  const MatchOptions& options) {
  std::vector<std::int64_t> cause_ns, effect_ns;
  cause_ns.reserve(causes.size());
  effect_ns.reserve(effects.size());
  const core::Clock clock = !causes.empty()    ? causes.front().time.clock()
                            : !effects.empty() ? effects.front().time.clock()
                                               : core::Clock::realtime;
  for (const auto& [events, out] : {std::pair{causes, &cause_ns}, std::pair{effects, &effect_ns}})
    for (const auto& event : events) {
      if (event.time.clock() != clock)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("cannot pair a {} timestamp with a {} timestamp (event on {}/{})",
                                      core::to_string(event.time.clock()), core::to_string(clock), event.node,
                                      event.channel));
      out->push_back(event.time.ns());
    }
  return match(std::span<const std::int64_t>(cause_ns), std::span<const std::int64_t>(effect_ns), clock,
               options);
}

}  // namespace m2mlat::pairing
