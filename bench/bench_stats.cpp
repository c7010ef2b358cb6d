// Statistics throughput: latencies per second summarised (n, extremes with their sample, mean, sd,
// the quantiles, the shares above the default thresholds), without and with the bootstrap CIs of
// median and IQR (Settings::bootstrap resamples), on the true pairs' latencies of the first n
// causes of the recording (about 0.93 n samples: some passes are missed on one side).
#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "m2mlat/stats/summary.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {

namespace {

struct Sample {
  std::vector<std::int64_t> latency_ns;
  std::vector<std::int64_t> ids;  // the cause's index, as the command line passes
};

Sample sample(std::size_t n) {
  const auto& r = recording();
  Sample s;
  for (const auto& p : r.truth) {
    if (p.cause >= n) continue;
    s.latency_ns.push_back(r.effect_ns[p.effect] - r.cause_ns[p.cause]);
    s.ids.push_back(static_cast<std::int64_t>(p.cause));
  }
  return s;
}

void add_summary(std::size_t n, std::size_t resamples) {
  add(fmt::format("stats/summarize/bootstrap:{}/events_per_side:{}", resamples, n),
      [=](benchmark::State& state) {
        const auto s = sample(n);
        stats::SummaryOptions options;
        if (resamples > 0) options.bootstrap = stats::BootstrapOptions{resamples, 1, 0.95};
        for (auto _ : state) {
          const auto summary = stats::summarize(s.latency_ns, s.ids, options);
          if (summary.n != s.latency_ns.size()) throw std::runtime_error("summary of the wrong sample size");
          benchmark::DoNotOptimize(&summary);
        }
        state.counters["latencies"] = static_cast<double>(s.latency_ns.size());
        set_rate(state, s.latency_ns.size(), "latencies");
      });
}

}  // namespace

void register_stats_benchmarks() {
  for (auto n : ladder()) {
    add_summary(n, 0);
    if (settings().bootstrap > 0) add_summary(n, settings().bootstrap);
  }
}

}  // namespace m2mlat::bench
