// Applying a setup plan: announce, then change (apply.hpp).
#include "m2mlat/setup/apply.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/setup/diff.hpp"
#include "m2mlat/process/command_runner.hpp"

namespace m2mlat::setup {

namespace fs = std::filesystem;

namespace {

constexpr auto kCommandTimeout = std::chrono::seconds(60);  // groupadd, udevadm, systemctl

[[noreturn]] void io_error(const std::string& path, const std::string& what) {
  throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", path, what));
}

void print_indented(std::FILE* out, std::string_view text, std::string_view prefix) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    auto end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    // A file on the system may hold anything: each line shown escaped (core/printable.hpp).
    fmt::print(out, "    {}{}\n", prefix, core::printable(text.substr(pos, end - pos)));
    pos = end + 1;
  }
}

// Kernel files (sysfs, procfs) are not regular files and take a value only when it is written into
// that very inode: core::write_output_file would refuse them, and they cannot be renamed over.
void write_in_place(const std::string& target, const std::string& content) {
  std::ofstream file(target, std::ios::out | std::ios::binary);  // no trunc/rename: a kernel file
  file << content;
  file.close();
  if (!file) io_error(target, "cannot write (root needed?)");
}

}  // namespace

void replace_file(const std::string& target, const std::string& content, int mode) {
  const fs::path dir = fs::path(target).parent_path();
  std::error_code ec;
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (ec) io_error(dir.string(), "cannot create: " + ec.message());
  if (core::check_output_target(target)) {  // a regular file (anything else is refused)
    struct stat st {};
    std::string current;
    if (::stat(target.c_str(), &st) != 0 || !read_target("/", target, current))
      io_error(target, "cannot read it to back it up");
    // The backup keeps the original's mode: a file readable by root only stays so.
    core::write_output_file(target + ".m2mlat-backup", current,
                            core::OutputFileOptions{.mode = static_cast<int>(st.st_mode & 07777)});
  }
  core::write_output_file(target, content, core::OutputFileOptions{.mode = mode});
}

std::string under_root(const std::string& root, const std::string& path) {
  if (root.empty() || root == "/") return path;
  return (fs::path(root) / fs::path(path).relative_path()).string();
}

bool read_target(const std::string& root, const std::string& path, std::string& content) {
  std::ifstream in(under_root(root, path), std::ios::binary);
  if (!in) return false;
  std::ostringstream s;
  s << in.rdbuf();
  content = s.str();
  return true;
}

ApplyResult apply_plan(const Plan& plan, const ApplyOptions& options) {
  ApplyResult result;
  std::FILE* out = options.out;
  const bool real_system = options.root.empty() || options.root == "/";
  std::set<std::string> changed;  // files (target paths) changed in this run
  std::set<std::string> done;     // command lines run (or announced) in this run
  fmt::print(out, "setup {}{}:\n", plan.part, options.dry_run ? " (dry run: nothing is changed)" : "");
  for (const auto& step : plan.steps) {
    if (step.kind == Step::Kind::file) {
      ++result.files_checked;
      const std::string target = under_root(options.root, step.path);
      std::string current;
      const bool exists = read_target(options.root, step.path, current);
      if (exists && current == step.content) {
        fmt::print(out, "{}: unchanged ({})\n", target, step.why);
        continue;
      }
      ++result.changes;
      changed.insert(step.path);
      const auto lines = std::count(step.content.begin(), step.content.end(), '\n');
      fmt::print(out, "{} {}: {} ({} lines)\n", options.dry_run ? "would write" : "writing", target,
                 step.why, lines);
      print_indented(out, step.content, "| ");
      if (exists && step.in_place) {
        print_indented(out, current, "was: ");
      } else if (exists) {
        fmt::print(out, "    {} {} to {}.m2mlat-backup; the changes:\n", options.dry_run ? "would copy" : "copying",
                   target, target);
        print_indented(out, line_diff(current, step.content, target), "");
      }
      if (options.dry_run) continue;
      if (step.in_place)
        write_in_place(target, step.content);
      else
        replace_file(target, step.content, static_cast<int>(step.mode));
    } else {
      const std::string line = process::command_line(step.argv);
      if (!step.after.empty() && changed.count(step.after) == 0) continue;  // its file did not change
      if (!done.insert(line).second) continue;  // e.g. one chrony restart for its conf and drop-in
      ++result.changes;
      if (options.dry_run) {
        fmt::print(out, "would run: {}   ({})\n", line, step.why);
        continue;
      }
      if (!real_system) {
        fmt::print(out, "not run under --root {}: {}   ({})\n", options.root, line, step.why);
        continue;
      }
      fmt::print(out, "running: {}   ({})\n", line, step.why);
      std::fflush(out);
      process::ProcessRunner runner;
      const auto r = runner.run(step.argv, kCommandTimeout);
      if (!r.ok()) {
        ++result.commands_failed;
        fmt::print(out, "    FAILED: {}\n", process::failure_text(r));
      }
    }
  }
  if (result.changes == 0)
    fmt::print(out, "nothing to change: already set up ({} files checked)\n", result.files_checked);
  else if (options.dry_run)
    fmt::print(out, "dry run: {} change(s) would be made, none made\n", result.changes);
  else
    fmt::print(out, "{} change(s) made{}\n", result.changes,
               result.commands_failed ? fmt::format(", {} command(s) FAILED", result.commands_failed) : "");
  for (const auto& note : plan.notes) fmt::print(out, "next: {}\n", note);
  std::fflush(out);
  return result;
}

}  // namespace m2mlat::setup
