// Matcher throughput: events per second (both sides counted) for pairing n events per side of the
// simulated multi-magnet recording with the default options (window 0..10 s, refractory 10 ms,
// no tolerance), as `m2mlat pair` and `stats` do.
//
// Beside it, the floor any pairing of the two sorted columns pays: a plain merge of the same two
// arrays into one sorted output (each input read once, 2n int64 written to a fresh vector, as the
// matcher writes its pairs to a fresh vector). bench/report.py prints the matcher's time over the
// merge's (target <= 1.2x).
//
// And the floor of any matcher that weighs every candidate pair in a cause's latency window, as
// issue 16's must (a stall of seconds puts the true effect anywhere in it): one pass of the least
// order-preserving chain over those candidates (window_dp below). The matcher runs three such passes,
// each with a value, the sweep's links and the back-tracking; bench/report.py prints its time over
// three of these (docs/benchmarks.md, "Why the two speed targets are blocked").
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "m2mlat/pairing/matcher.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {
namespace {

// The longest order-preserving chain of pairs with effect - cause in [0, window_ns]: per candidate one
// running maximum (over the effects before it, from the causes before this one) and its predecessor
// written, per cause its row folded into each effect's best. The predecessors go round a ring of
// 2^20 (4 MiB), as the matcher's back-tracking reuses its settled blocks. Returns the chain's length.
std::uint32_t window_dp(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
                        std::int64_t window_ns, std::vector<std::uint32_t>& predecessors) {
  constexpr std::size_t kRingMask = (std::size_t{1} << 20) - 1;
  predecessors.resize(kRingMask + 1);
  std::vector<std::uint32_t> best(effects.size(), 0), best_id(effects.size(), 0);
  std::vector<std::uint32_t> row;
  std::uint32_t frozen = 0, frozen_id = 0;  // the best over the effects behind every later window
  std::size_t lo = 0, hi = 0, folded = 0, id = 0;
  for (const std::int64_t cause : causes) {
    while (lo < effects.size() && effects[lo] < cause) ++lo;
    while (hi < effects.size() && effects[hi] - cause <= window_ns) ++hi;
    for (; folded < lo; ++folded) {
      const bool up = best[folded] > frozen;
      frozen = up ? best[folded] : frozen;
      frozen_id = up ? best_id[folded] : frozen_id;
    }
    std::uint32_t running = frozen, running_id = frozen_id;
    row.resize(hi - lo);
    const std::size_t first_id = id;  // this row's candidates are first_id, first_id + 1, ...
    for (std::size_t j = lo; j < hi; ++j) {
      row[j - lo] = running + 1;
      predecessors[id++ & kRingMask] = running_id;
      const bool up = best[j] > running;
      running = up ? best[j] : running;
      running_id = up ? best_id[j] : running_id;
    }
    for (std::size_t j = lo; j < hi; ++j) {
      const bool up = row[j - lo] > best[j];
      best[j] = up ? row[j - lo] : best[j];
      best_id[j] = up ? static_cast<std::uint32_t>(first_id + (j - lo)) : best_id[j];
    }
  }
  for (; folded < effects.size(); ++folded) frozen = std::max(frozen, best[folded]);
  return frozen;
}

}  // namespace

namespace {

// `match` with `options` on the first n edges a side, as benchmark `name`.
void add_match(const std::string& name, std::size_t n, pairing::MatchOptions options) {
  add(fmt::format("{}/events_per_side:{}", name, n), [n, options](benchmark::State& state) {
    const auto input = prefix(n, options.max_latency.count());
    std::size_t pairs = 0;
    for (auto _ : state) {
      const auto result = pairing::match(input.cause_ns, input.effect_ns, core::Clock::realtime, options);
      pairs = result.pairs.size();
      benchmark::DoNotOptimize(&result);
    }
    if (pairs == 0) throw std::runtime_error("the matcher found no pairs");
    state.counters["pairs"] = static_cast<double>(pairs);
    set_rate(state, input.cause_ns.size() + input.effect_ns.size(), "events");
  });
}

}  // namespace

void register_pairing_benchmarks() {
  for (auto n : ladder()) {
    add_match("pairing/match", n, {});
    // The alignment model (`--matcher model`): its lattice is not narrowed (docs/matcher.md, "Pairing
    // as inference"), so only the smaller rungs.
    if (n <= 100'000) {
      pairing::MatchOptions model;
      model.method = pairing::MatchOptions::Method::model;
      add_match("pairing/match_model", n, model);
    }
    add(fmt::format("pairing/merge_floor/events_per_side:{}", n), [n](benchmark::State& state) {
      const auto input = prefix(n, pairing::MatchOptions{}.max_latency.count());
      for (auto _ : state) {
        std::vector<std::int64_t> merged(input.cause_ns.size() + input.effect_ns.size());
        std::merge(input.cause_ns.begin(), input.cause_ns.end(), input.effect_ns.begin(), input.effect_ns.end(),
                   merged.begin());
        benchmark::DoNotOptimize(merged.data());
        benchmark::ClobberMemory();
      }
      set_rate(state, input.cause_ns.size() + input.effect_ns.size(), "events");
    });
    add(fmt::format("pairing/window_dp_floor/events_per_side:{}", n), [n](benchmark::State& state) {
      const auto window_ns = pairing::MatchOptions{}.max_latency.count();
      const auto input = prefix(n, window_ns);
      std::vector<std::uint32_t> predecessors;
      std::uint32_t chain = 0;
      for (auto _ : state) {
        chain = window_dp(input.cause_ns, input.effect_ns, window_ns, predecessors);
        benchmark::DoNotOptimize(chain);
      }
      if (chain == 0) throw std::runtime_error("the window's chain is empty");
      state.counters["chain"] = static_cast<double>(chain);
      set_rate(state, input.cause_ns.size() + input.effect_ns.size(), "events");
    });
  }
}

}  // namespace m2mlat::bench
