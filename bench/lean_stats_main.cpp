// m2mlat_lean_stats: import -> pair -> statistics of two kernel logs on the library's lean path,
// timed step by step; the m2mlat side of bench/run.sh's per-step comparison with the baseline.
//
//   m2mlat_lean_stats CAUSE.log EFFECT.log BOOTSTRAP_RESAMPLES
//
// Reads each file as one timestamp column (formats::read_timestamps: no core::Event objects), pairs
// with pairing::match (default options, as `m2mlat stats`), summarises the pairs not flagged
// ambiguous (as `m2mlat stats` does by default) with stats::summarize_in_place (the default thresholds;
// bootstrap CIs of median and IQR when resamples > 0, seed 1, level 0.95), and
// prints one JSON object: the summary's main figures, the event counts and the seconds per step
// ("timing_s": import, pair, statistics - the last including the bootstrap). bench/measure.py gives
// its wall time and peak memory.
#include <fmt/format.h>

#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<std::int64_t> read_side(const std::string& path) {
  auto series = m2mlat::formats::read_timestamps(path, m2mlat::formats::Format::kernel_log);
  if (series.size() != 1)
    throw m2mlat::core::Error(
        m2mlat::core::ErrorKind::data,
        fmt::format("{}: expected the timestamps of one GPIO pin, found {}", path, series.size()));
  return std::move(series.front().ns);
}

int run(const std::string& cause_path, const std::string& effect_path, std::size_t resamples) {
  nlohmann::json timing;
  auto start = Clock::now();
  auto causes = read_side(cause_path);
  auto effects = read_side(effect_path);
  timing["import"] = seconds_since(start);

  start = Clock::now();
  // In place, as `m2mlat stats` pairs: the columns are this program's, and come back unchanged.
  const auto match = m2mlat::pairing::match_in_place(causes, effects, m2mlat::core::Clock::realtime);
  std::vector<std::int64_t> latencies;
  latencies.reserve(match.pairs.size());
  for (const auto& p : match.pairs)
    if (!p.ambiguous())  // as `m2mlat stats` does by default
      latencies.push_back(effects[p.effect_index] - causes[p.cause_index]);
  timing["pair"] = seconds_since(start);

  start = Clock::now();
  m2mlat::stats::SummaryOptions options;
  if (resamples > 0) options.bootstrap = m2mlat::stats::BootstrapOptions{resamples, 1, 0.95};
  const auto s = m2mlat::stats::summarize_in_place(latencies, {}, options);  // no ids: none is printed
  timing["statistics"] = seconds_since(start);

  nlohmann::json out = {{"pairs", match.pairs.size()},
                        {"n", s.n},
                        {"mean_ms", s.mean_ms},
                        {"sd_ms", s.sd_ms},
                        {"q1", s.q1_ms},
                        {"median", s.median_ms},
                        {"q3", s.q3_ms},
                        {"p99", s.p99_ms},
                        {"iqr", s.iqr_ms},
                        {"events", {{"cause", causes.size()}, {"effect", effects.size()}}},
                        {"timing_s", timing}};
  if (s.bootstrap) {
    out["median_ci"] = {s.bootstrap->median_ms.lower, s.bootstrap->median_ms.upper};
    out["iqr_ci"] = {s.bootstrap->iqr_ms.lower, s.bootstrap->iqr_ms.upper};
  }
  std::puts(out.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t resamples = 0;
  if (argc != 4 ||
      std::from_chars(argv[3], argv[3] + std::string_view(argv[3]).size(), resamples).ec != std::errc()) {
    std::fprintf(stderr, "usage: m2mlat_lean_stats CAUSE.log EFFECT.log BOOTSTRAP_RESAMPLES\n");
    return 2;
  }
  try {
    return run(argv[1], argv[2], resamples);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "m2mlat_lean_stats: %s\n", e.what());
    return 1;
  }
}
