// Matcher throughput: events per second (both sides counted) for pairing n events per side of the
// simulated multi-magnet recording with the default options (window 0..10 s, refractory 10 ms,
// no tolerance), as `m2mlat pair` and `stats` do.
//
// Beside it, the floor any pairing of the two sorted columns pays: a plain merge of the same two
// arrays into one sorted output (each input read once, 2n int64 written to a fresh vector, as the
// matcher writes its pairs to a fresh vector). bench/report.py prints the matcher's time over the
// merge's (target <= 1.2x).
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "m2mlat/pairing/matcher.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {

void register_pairing_benchmarks() {
  for (auto n : ladder()) {
    add(fmt::format("pairing/match/events_per_side:{}", n), [n](benchmark::State& state) {
      const pairing::MatchOptions options;
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
  }
}

}  // namespace m2mlat::bench
