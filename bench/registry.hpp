// Registering the benchmarks: one function per group (import, store, pairing, statistics, the whole
// pipeline), each adding its cases for the sizes of the run (Settings, set from the command line).
//
// Every case measures wall-clock time (UseRealTime: a commit waiting for fsync is idle, not busy)
// and reports its rate as items_per_second, the items being named by the case's label: "lines"
// (data lines of an input file), "events" (both sides counted), "latencies" (samples summarised).
#pragma once

#include <benchmark/benchmark.h>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <utility>

namespace m2mlat::bench {

void register_import_benchmarks();
void register_store_benchmarks();
void register_pairing_benchmarks();
void register_stats_benchmarks();
void register_pipeline_benchmarks();

// Registers `body(state)` under `name`, in milliseconds of wall-clock time. An exception from the
// body ends the case with its message instead of the whole program.
template <typename Body>
benchmark::internal::Benchmark* add(const std::string& name, Body body) {
  return benchmark::RegisterBenchmark(name.c_str(),
                                      [body = std::move(body)](benchmark::State& state) {
                                        try {
                                          body(state);
                                        } catch (const std::exception& e) {
                                          state.SkipWithError(e.what());
                                        }
                                      })
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

// Sets the rate of a case: `per_iteration` items of kind `label` per iteration.
inline void set_rate(benchmark::State& state, std::size_t per_iteration, const char* label) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(per_iteration));
  state.SetLabel(label);
}

}  // namespace m2mlat::bench
