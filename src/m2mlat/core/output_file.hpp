// Output files: the one way m2mlat writes a file the user named (exports, reports, figures, the
// agent's port file, configuration written by `setup`).
//
// The content goes to a new temporary file in the target's own folder, created under a random
// name with O_CREAT|O_EXCL|O_NOFOLLOW (so a planted file or symlink under a guessable name cannot
// redirect the write), is flushed to disk (fsync), and is then renamed over the target: a reader
// sees the old file or the new one, never half of one, and a failure leaves the target as it was
// and no temporary behind. The target itself is examined with lstat(): it may be missing or a
// regular file; anything else (a symlink, a character or block device such as /dev/null, a
// directory, a FIFO, a socket) is refused with an error naming the path and what it is, so that an
// export never turns a device into a regular file nor writes through a link. A regular file this
// process has open (an input, a store: `export STORE -o STORE`) is refused too. "-" means standard
// output.
//
// Kernel interfaces (/proc, /sys) are not regular files and are written in place by rt/ and setup/.
#pragma once

#include <functional>
#include <ostream>
#include <string>
#include <string_view>

namespace m2mlat::core {

struct OutputFileOptions {
  // Permission bits of the written file (e.g. 0644); -1: those of the regular file it replaces,
  // or 0666 less the umask for a new file.
  int mode = -1;
};

// Writes `path` through `write` as described above; "-" writes to standard output. Throws
// core::Error(io) naming the path when the target is refused or any step fails; an exception
// thrown by `write` is passed on after the temporary file is removed.
void write_output_file(const std::string& path, const std::function<void(std::ostream&)>& write,
                       const OutputFileOptions& options = {});
void write_output_file(const std::string& path, std::string_view content,
                       const OutputFileOptions& options = {});

// Checks a target before anything is written: true when a regular file is there, false when
// nothing is; throws core::Error(io) naming the path and its type for anything else.
bool check_output_target(const std::string& path);

}  // namespace m2mlat::core
