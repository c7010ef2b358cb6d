// Shared by the setup tests: a temporary root folder, and applying a plan into it with the
// announcements captured as text.
#pragma once

#include <stdio.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "m2mlat/setup/apply.hpp"
#include "temp_dir.hpp"

namespace m2mlat::setup::testing {

// A temporary folder standing for the root of a board's file system.
class TempRoot {
 public:
  const std::string& path() const { return path_; }
  std::string file(const std::string& target) const { return under_root(path_, target); }
  void write(const std::string& target, const std::string& content) const {
    std::filesystem::create_directories(std::filesystem::path(file(target)).parent_path());
    std::ofstream(file(target)) << content;
  }
  std::string read(const std::string& target) const {
    std::ifstream in(file(target));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  m2mlat::testing::TempDir dir_;
  std::string path_ = dir_.path().string();
};

struct Applied {
  ApplyResult result;
  std::string text;
};

inline Applied apply_into(const Plan& plan, const std::string& root, bool dry_run = false) {
  char* buffer = nullptr;
  std::size_t size = 0;
  FILE* out = ::open_memstream(&buffer, &size);
  Applied a;
  a.result = apply_plan(plan, ApplyOptions{root, dry_run, out});
  std::fclose(out);
  a.text.assign(buffer, size);
  std::free(buffer);
  return a;
}

}  // namespace m2mlat::setup::testing
