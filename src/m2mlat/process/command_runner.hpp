// Running external programs (chronyc and pmc for a clock's state, cyclictest for the scheduling
// test, groupadd/udevadm/systemctl for setup) behind one small interface, so that their callers are
// tested with recorded outputs (a scripted runner) and use the real programs in production
// (ProcessRunner). A failed run is described in one format everywhere (failure_text, command_error):
//   "<command line>: exit status 1: <what it said>" | "...: timed out" | "...: <why not started>".
// This folder depends on core only, so that sync, selftest and setup can all use it.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::process {

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

// Why a run failed, for messages: the reason it was not started, "timed out", or "exit status N"
// followed by what the program said (its standard error, or its standard output when the error is
// empty), trimmed, cut to 300 bytes and escaped for the terminal (core::printable). "" when ok().
std::string failure_text(const CommandResult& result);

// core::Error(io) "<command line>: <failure_text>", for a run that failed.
core::Error command_error(const std::vector<std::string>& argv, const CommandResult& result);

}  // namespace m2mlat::process
