// Matcher throughput: events per second (both sides counted) for pairing n events per side of the
// simulated multi-magnet recording with the default options (window 0..3 s, refractory 10 ms,
// tolerance 1 s), as `m2mlat pair` and `stats` do.
#include <fmt/format.h>

#include <stdexcept>

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
  }
}

}  // namespace m2mlat::bench
