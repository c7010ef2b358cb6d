// A board that followed the other's clock step, seen across `m2mlat import`s. kernel_log_followed
// reads a board's own printk stamps against the other board's steps, and the store keeps no printk
// stamps: so `import` reads the follow while it holds a kernel log's stamps, both ways:
//   - a kernel log against the steps the store already holds for the scenario's other nodes;
//   - a kernel log imported earlier (its session's "file", re-read) against this import's steps.
//     The earlier file must still hold every event stored from it; if it does not (moved, changed),
//     its board's stamps after each such step are left out as after a step of unknown size (origin
//     "follow_unchecked"), and a note says how to avoid it: a wrong latency is never left unflagged.
// Without it a store built from a co-referenced rig's kernel logs corrected the stepped board's
// events and not the follower's: every later latency off by the step.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

// One board's kernel log as an import reads it (lines with the log's own stamp only).
struct ImportedLog {
  std::string node, scenario;
  std::vector<std::int64_t> realtime_ns, log_time_us;  // per line, in file order
  std::vector<store::ClockStep> steps;                  // kernel_log_clock's
};

// Steps taken over by a board whose kernel log was imported before: to be stored as a session of
// its own (no events) of that node and scenario.
struct EarlierFollow {
  store::Session earlier;  // the stored session whose board took the steps over
  std::vector<store::ClockStep> steps;
  bool checked = true;  // false: the file could not be re-read, the steps are of unknown size
};

struct ImportFollow {
  std::vector<std::vector<store::ClockStep>> of_log;  // per ImportedLog, in order
  std::vector<EarlierFollow> earlier;
  std::vector<std::string> notes;  // for stderr: an earlier file that could not be re-read
};

// `store` is only read.
ImportFollow follow_across_import(std::span<const ImportedLog> logs, const store::Store& store);

}  // namespace m2mlat::analysis
