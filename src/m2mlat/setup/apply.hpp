// Carrying out a setup plan (plan.hpp), announcing every change before making it: a file's path,
// its full new content and, when it replaces an existing file, the backup and the diff; a command's
// line. The one writer of setup's files: every part, `setup chrony` included, goes through it. With
// dry_run nothing is changed. Files are written by core::write_output_file (a temporary file in the
// same folder, renamed over the target; a target that is not a regular file, e.g. a symlink, is
// refused) and an existing, different file is kept as <path>.m2mlat-backup; kernel files
// (in_place) are written directly.
// Commands run only on the real system (root "/"): under another root they are printed as
// "not run" (they act on the running system, not on the folder).
#pragma once

#include <cstdio>
#include <string>

#include "m2mlat/setup/plan.hpp"

namespace m2mlat::setup {

struct ApplyOptions {
  std::string root = "/";  // the target system's root folder
  bool dry_run = false;
  std::FILE* out = stdout;  // where the changes are announced
};

struct ApplyResult {
  int files_checked = 0;
  int changes = 0;  // files written (or that would be) and commands run (or that would be)
  int commands_failed = 0;
};

// `path` (absolute, on the target system) under `root`.
std::string under_root(const std::string& root, const std::string& path);
// The content of a file under the root, or nullopt-like empty + false when it does not exist.
bool read_target(const std::string& root, const std::string& path, std::string& content);

// Replaces the file `target` with `content` (permission bits `mode`, e.g. 0644): creates its folder
// if missing, keeps a regular file already there as <target>.m2mlat-backup (same mode), then
// writes through core::write_output_file. Throws core::Error(io) naming the path, and refuses a
// target or backup that is a symlink, a device or anything else but a regular file.
void replace_file(const std::string& target, const std::string& content, int mode);

// Applies the plan. Throws core::Error(io) when a file cannot be written (the steps before it stay
// done; each is complete on its own). A failing command is reported and counted, not thrown.
ApplyResult apply_plan(const Plan& plan, const ApplyOptions& options);

}  // namespace m2mlat::setup
