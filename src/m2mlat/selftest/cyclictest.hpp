// cyclictest (Debian's rt-tests) as m2mlat's scheduling test: how late a SCHED_FIFO thread on the
// capture core wakes up after its timer expires. The reference rig ran
//   cyclictest --mlockall --priority=99 --affinity=C --threads=1 --interval=1000
//              --duration=Ns --histogram=N --json=FILE -q
// which writes a histogram as text on stdout and a JSON summary to FILE. All latencies are in
// microseconds (cyclictest's unit without --nsecs).
//
// JSON (rt-tests 2.x, file_version 1): {"file_version", "cmdline:", "rt_test_version:",
// "start_time", "end_time", "return_code", "sysinfo": {..., "release", "realtime"}, "num_threads",
// "thread": {"0": {"histogram": {"<us>": count, ...}, "cycles", "min", "max", "avg", "cpu", "node"}}}
// (the colons inside two key names are cyclictest's own). Text: one line per bucket "000017 000068"
// (bucket in us, then one count per thread), then "# Total:", "# Min Latencies:",
// "# Avg Latencies:", "# Max Latencies:", "# Histogram Overflows:" with one value per thread.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/process/command_runner.hpp"

namespace m2mlat::selftest {

struct CyclictestThread {
  int cpu = -1;
  std::uint64_t cycles = 0;  // timer wake-ups measured
  std::int64_t min_us = 0, max_us = 0;
  double avg_us = 0;
  std::vector<std::pair<std::int64_t, std::uint64_t>> histogram;  // (bucket us, count), non-zero, ascending
  std::uint64_t overflows = 0;  // wake-ups later than the histogram's range (cycles - histogram total)
};

struct CyclictestResult {
  std::string version;  // rt-tests version
  std::string cmdline;
  std::string start_time, end_time;  // as cyclictest wrote them
  int return_code = 0;
  std::string kernel_release;
  bool realtime_kernel = false;  // sysinfo.realtime: a PREEMPT_RT kernel
  std::vector<CyclictestThread> threads;
};

// Histogram text as cyclictest prints it with --histogram (one column per thread).
struct CyclictestHistogram {
  std::vector<std::vector<std::uint64_t>> counts;  // [thread][bucket us]
  std::vector<std::uint64_t> total, overflows;
  std::vector<std::int64_t> min_us, avg_us, max_us;  // per thread (avg as cyclictest rounded it)
};

// Pure parsers (no I/O), for tests and fuzzing. Errors: core::Error(data) naming `where` and the
// line or field.
CyclictestResult parse_cyclictest_json(std::string_view text, const core::Location& where);
CyclictestHistogram parse_cyclictest_histogram(std::string_view text, const core::Location& where);

struct CyclictestOptions {
  std::string program = "cyclictest";
  int cpu = 0;                                        // --affinity
  int priority = 99;                                  // --priority (SCHED_FIFO)
  int interval_us = 1000;                             // --interval
  core::Duration duration = std::chrono::seconds(5);  // --duration (whole seconds)
  int histogram_us = 1000;                            // --histogram: buckets of 1 us up to this
};

// The cyclictest command line for a run writing its JSON to json_path.
std::vector<std::string> cyclictest_argv(const CyclictestOptions& options, const std::string& json_path);

// Runs cyclictest (root or CAP_SYS_NICE + CAP_IPC_LOCK needed for SCHED_FIFO and mlockall), reads
// its JSON and histogram and checks that they agree. Throws core::Error(io) when it cannot run or
// fails (with its message), core::Error(data) when its output does not parse or disagrees.
CyclictestResult run_cyclictest(process::CommandRunner& runner, const CyclictestOptions& options);

}  // namespace m2mlat::selftest
