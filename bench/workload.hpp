// The input every benchmark runs on: a simulated field recording, generated once per run and shared.
//
// The rig is the one bench/run.sh simulates for the end-to-end comparison (preset static_5g, three
// magnets 20 degrees apart, the field sensor's misses, bounces and spurious edges, seed 1), so the
// micro-benchmarks see the same kind of data as the command-line run: bursts of edges tens of ms
// apart, ~0.9 s latency. Only timestamp columns are kept in memory (int64 ns, CLOCK_REALTIME), so
// that 10^7 events per side cost 160 MB, not the gigabytes of core::Event objects.
//
// The input files of the import benchmarks (kernel log, the rig's export and paired CSVs, m2mlat's
// events CSV) are written on first use into a temporary directory that is removed at exit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace m2mlat::bench {

// A directory under $TMPDIR (or /tmp), removed with everything in it when the object goes away.
class TempDir {
 public:
  TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// The sizes of one run, set once from the command line before any benchmark runs.
struct Settings {
  std::size_t events = 10'000'000;  // events per side (and lines per import file)
  std::size_t bootstrap = 200;      // bootstrap resamples of the statistics cases that have them
};

// One cause/effect pair as the simulator knows it: indices into the two timestamp columns.
struct TrueIndexPair {
  std::size_t cause = 0;
  std::size_t effect = 0;
};

// The simulated recording, sized by Settings::events.
struct Recording {
  std::vector<std::int64_t> cause_ns;   // operator board, sorted, CLOCK_REALTIME ns
  std::vector<std::int64_t> effect_ns;  // vehicle board, sorted, CLOCK_REALTIME ns
  std::vector<TrueIndexPair> truth;     // the passes seen on both sides (both indices in range)
};

// Files holding the recording in each importable format, and their data line counts.
struct InputFiles {
  std::string kernel_log;         // GPIO_16_IRQ:<ns>, the cause side
  std::string kernel_log_effect;  // the same for the effect side (for the whole pipeline)
  std::string rig_export_csv;     // Line,Seconds,Nanoseconds, the cause side
  std::string rig_paired_csv;     // remote_station_s,...,m2m_latency_ms, one row per true pair
  std::string events_csv;         // m2mlat-events/1, the cause side
  std::size_t kernel_log_lines = 0;
  std::size_t rig_export_lines = 0;
  std::size_t rig_paired_lines = 0;
  std::size_t events_csv_lines = 0;
};

void configure(const Settings& settings);
const Settings& settings();

// Generated on first call (a few seconds for 10^7 events per side), then shared.
const Recording& recording();
// Written on first call, into the run's temporary directory.
const InputFiles& input_files();
// The run's temporary directory (for stores); created on first call, removed by release_workload().
const std::filesystem::path& scratch_dir();
// Frees the recording and removes the temporary directory. Called once, after the last benchmark.
void release_workload();

// The first n causes and the effects up to the last of those causes plus `window_ns`, so that a
// prefix of the recording is a complete smaller recording (every cause keeps its candidates).
struct Prefix {
  std::span<const std::int64_t> cause_ns;
  std::span<const std::int64_t> effect_ns;
};
Prefix prefix(std::size_t n, std::int64_t window_ns);

// The sizes (events per side) of the pairing and statistics cases: 10^5, 10^6, 10^7 up to
// Settings::events, and Settings::events itself.
std::vector<std::size_t> ladder();

}  // namespace m2mlat::bench
