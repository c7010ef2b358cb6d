// The whole analysis in one process, on the lean path the library offers for large files: both
// kernel logs read as timestamp columns (read_timestamps), paired, and the pairs not flagged
// ambiguous summarised, without and with the bootstrap. Events per second count both sides. The
// same work as `m2mlat stats --cause-file --effect-file`, minus building core::Event objects and
// printing JSON; the difference between the two is the cost of the command line's way through the
// library.
#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {

namespace {

std::vector<std::int64_t> read_side(const std::string& path) {
  auto series = formats::read_timestamps(path, formats::Format::kernel_log);
  if (series.size() != 1) throw std::runtime_error(path + ": expected the timestamps of one pin");
  return std::move(series.front().ns);
}

void add_pipeline(std::size_t resamples) {
  add(fmt::format("pipeline/lean/bootstrap:{}/events_per_side:{}", resamples, settings().events),
      [=](benchmark::State& state) {
        const auto& files = input_files();
        stats::SummaryOptions summary_options;
        if (resamples > 0) summary_options.bootstrap = stats::BootstrapOptions{resamples, 1, 0.95};
        std::size_t events = 0;
        for (auto _ : state) {
          auto causes = read_side(files.kernel_log);
          auto effects = read_side(files.kernel_log_effect);
          const auto match = pairing::match_in_place(causes, effects, core::Clock::realtime);
          std::vector<std::int64_t> latencies, ids;
          latencies.reserve(match.pairs.size());
          ids.reserve(match.pairs.size());
          for (const auto& p : match.pairs) {
            if (p.ambiguous()) continue;  // as `m2mlat stats` does by default
            latencies.push_back(effects[p.effect_index] - causes[p.cause_index]);
            ids.push_back(p.cause_index);
          }
          const auto summary = stats::summarize(latencies, ids, summary_options);
          benchmark::DoNotOptimize(&summary);
          events = causes.size() + effects.size();
        }
        set_rate(state, events, "events");
      });
}

}  // namespace

void register_pipeline_benchmarks() {
  add_pipeline(0);
  if (settings().bootstrap > 0) add_pipeline(settings().bootstrap);
}

}  // namespace m2mlat::bench
