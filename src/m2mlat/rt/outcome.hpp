// The result of one real-time setting: done, or a message saying what was refused and which
// privilege would allow it. The recorder and the pulse generator apply several settings in a row
// and report each one; none of them is worth aborting a capture for unless the user asked for it.
#pragma once

#include <string>
#include <utility>

namespace m2mlat::rt {

struct Outcome {
  bool ok = true;
  std::string message;  // what was done, or what was refused and how to allow it

  static Outcome success(std::string what) { return {true, std::move(what)}; }
  static Outcome failure(std::string why) { return {false, std::move(why)}; }
  explicit operator bool() const { return ok; }
};

}  // namespace m2mlat::rt
