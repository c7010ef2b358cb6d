// Running the external programs that report a clock's state (chronyc, pmc) and the scheduling test
// (cyclictest) behind one small interface, so that the parsers and the monitor are tested with
// recorded outputs (a scripted runner) and use the real programs in production (ProcessRunner).
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::sync {

struct CommandResult {
  bool started = false;    // false: the program could not be run at all (not installed, ...)
  bool timed_out = false;  // killed after the timeout
  int exit_code = -1;      // the program's exit status; -1 when it did not exit normally
  std::string out;         // its standard output
  std::string err;         // its standard error (or why it could not be started)
  bool ok() const { return started && !timed_out && exit_code == 0; }
};

class CommandRunner {
 public:
  virtual ~CommandRunner() = default;
  // Runs argv[0] (looked up in PATH) with the arguments, standard input from /dev/null, and
  // returns once it exited or `timeout` passed (then it is killed with SIGKILL).
  virtual CommandResult run(const std::vector<std::string>& argv, core::Duration timeout) = 0;
};

// Runs real processes (posix_spawnp, pipes, poll). Thread-compatible: one call at a time per object.
class ProcessRunner final : public CommandRunner {
 public:
  CommandResult run(const std::vector<std::string>& argv, core::Duration timeout) override;
};

// "chronyc -c tracking" as one line, for messages; arguments with spaces are quoted.
std::string command_line(const std::vector<std::string>& argv);

}  // namespace m2mlat::sync
