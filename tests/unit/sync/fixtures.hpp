// Test helpers of the sync tests: recorded outputs from tests/data/sync and a scripted command
// runner that answers with them, recording what it was asked to run.
#pragma once

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "m2mlat/process/command_runner.hpp"

namespace m2mlat::sync::testing {

inline std::string fixture(const std::string& name) {
  const std::string path = std::string(M2MLAT_TEST_DATA) + "/sync/" + name;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("missing fixture " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Answers every run with the next scripted result (the last one repeats), keeping the argv asked for.
class ScriptedRunner final : public process::CommandRunner {
 public:
  std::vector<process::CommandResult> results;
  std::vector<std::vector<std::string>> calls;
  process::CommandResult run(const std::vector<std::string>& argv, core::Duration) override {
    calls.push_back(argv);
    if (results.empty()) throw std::logic_error("no scripted result");
    const std::size_t i = std::min(calls.size() - 1, results.size() - 1);
    return results[i];
  }
  static process::CommandResult exited(int code, std::string out, std::string err = {}) {
    process::CommandResult r;
    r.started = true;
    r.exit_code = code;
    r.out = std::move(out);
    r.err = std::move(err);
    return r;
  }
};

}  // namespace m2mlat::sync::testing
