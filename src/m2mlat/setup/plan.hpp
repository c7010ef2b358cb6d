// What a `m2mlat setup` part wants to change on a board, as plain data: each part is a pure function
// from its options (and the text of the system files it looks at) to a Plan, so that the dry run,
// the real run and the tests all see the same list. Applying a plan is apply.hpp's job.
//
// A step is either a file with its whole new content, or a command. Paths are those on the target
// system (/etc/...); `--root DIR` puts them under DIR when applying. A command may depend on a file
// (`after`): it runs only when that file changed in the same run (reload udev after a new rule), so
// that a second run of the same plan changes nothing.
#pragma once

#include <string>
#include <vector>

namespace m2mlat::setup {

struct Step {
  enum class Kind { file, command };
  Kind kind = Kind::file;
  std::string why;  // one line, printed before the change

  // Kind::file
  std::string path;       // absolute path on the target system
  std::string content;    // the whole new content
  unsigned mode = 0644;   // permission bits of a new or replaced file
  bool in_place = false;  // a kernel file (/proc/irq/N/...): written as is, no backup, no rename

  // Kind::command
  std::vector<std::string> argv;
  std::string after;  // run only when this file (a path of an earlier step) changed; "" = always
};

Step file_step(std::string path, std::string content, std::string why);
Step command_step(std::vector<std::string> argv, std::string why, std::string after = {});

struct Plan {
  std::string part;                // "gpio", "irq", ... (for the headings)
  std::vector<Step> steps;         // in order
  std::vector<std::string> notes;  // printed after the steps: what to do next, what was not done
  void append(const Plan& other);  // other's steps and notes after this one's
};

}  // namespace m2mlat::setup
