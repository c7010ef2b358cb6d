// m2mlat_bench: the micro-benchmarks of import, store, pairing and statistics (Google Benchmark).
//
//   m2mlat_bench [--events N] [--bootstrap B] [--benchmark_* flags]
//
// --events N: events per side of the simulated recording, lines of each import file, and the
// largest size of the pairing and statistics cases (default 10,000,000). --bootstrap B: resamples
// of the statistics cases with confidence intervals (default 200; 0 leaves those cases out).
// Every input is generated on first use in a temporary directory under $TMPDIR (or /tmp), which is
// removed at the end. bench/run.sh runs this with --benchmark_format=json and prints the table.
#include <benchmark/benchmark.h>

#include <charconv>
#include <cstdio>
#include <exception>
#include <string>
#include <string_view>

#include "m2mlat/core/version.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace {

constexpr const char* kUsage =
    "usage: m2mlat_bench [--events N] [--bootstrap B] [--benchmark_* flags, see --help]\n";

bool parse_count(std::string_view text, std::size_t& value) {
  const auto* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end;
}

// Reads --events and --bootstrap (as "--flag N" or "--flag=N") from what Google Benchmark left.
bool parse(int argc, char** argv, m2mlat::bench::Settings& settings) {
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i], value;
    std::size_t* target = nullptr;
    for (auto [flag, field] : {std::pair{std::string_view("--events"), &settings.events},
                               std::pair{std::string_view("--bootstrap"), &settings.bootstrap}}) {
      if (arg == flag && i + 1 < argc) {
        target = field;
        value = argv[++i];
      } else if (arg.starts_with(flag) && arg.substr(flag.size()).starts_with("=")) {
        target = field;
        value = arg.substr(flag.size() + 1);
      }
      if (target != nullptr) break;
    }
    if (target == nullptr || !parse_count(value, *target)) {
      std::fprintf(stderr, "m2mlat_bench: bad argument '%s'\n%s", argv[i], kUsage);
      return false;
    }
  }
  if (settings.events < 1000) {
    std::fprintf(stderr, "m2mlat_bench: --events must be at least 1000\n");
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  m2mlat::bench::Settings settings;
  if (!parse(argc, argv, settings)) return 2;
  m2mlat::bench::configure(settings);
  benchmark::AddCustomContext("m2mlat_version", m2mlat::core::kVersion);
  benchmark::AddCustomContext("events_per_side", std::to_string(settings.events));
  benchmark::AddCustomContext("bootstrap_resamples", std::to_string(settings.bootstrap));
  benchmark::AddCustomContext("input", "simulated static_5g, magnets 0,20,40 deg, field sensors, seed 1");
  int status = 0;
  try {
    m2mlat::bench::register_import_benchmarks();
    m2mlat::bench::register_store_benchmarks();
    m2mlat::bench::register_pairing_benchmarks();
    m2mlat::bench::register_stats_benchmarks();
    m2mlat::bench::register_pipeline_benchmarks();
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "m2mlat_bench: %s\n", e.what());
    status = 1;
  }
  benchmark::Shutdown();
  m2mlat::bench::release_workload();
  return status;
}
