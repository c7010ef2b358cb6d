// Constructors of setup steps and plans (plan.hpp).
#include "m2mlat/setup/plan.hpp"

#include <utility>

namespace m2mlat::setup {

Step file_step(std::string path, std::string content, std::string why) {
  Step s;
  s.kind = Step::Kind::file;
  s.path = std::move(path);
  s.content = std::move(content);
  s.why = std::move(why);
  return s;
}

Step command_step(std::vector<std::string> argv, std::string why, std::string after) {
  Step s;
  s.kind = Step::Kind::command;
  s.argv = std::move(argv);
  s.why = std::move(why);
  s.after = std::move(after);
  return s;
}

void Plan::append(const Plan& other) {
  steps.insert(steps.end(), other.steps.begin(), other.steps.end());
  notes.insert(notes.end(), other.notes.begin(), other.notes.end());
}

}  // namespace m2mlat::setup
