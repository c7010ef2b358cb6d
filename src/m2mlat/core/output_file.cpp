// The output-file writer (output_file.hpp): temporary beside the target, fsync, rename.
#include "m2mlat/core/output_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>
#include <streambuf>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"

namespace m2mlat::core {

namespace {

[[noreturn]] void io_error(const std::string& path, const std::string& what, int err = 0) {
  throw Error(ErrorKind::io, err != 0 ? fmt::format("{}: {}: {}", path, what, std::strerror(err))
                                      : fmt::format("{}: {}", path, what));
}

const char* type_name(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// True when this process holds a descriptor of the file `target` describes: an input it is still
// reading, or an SQLite store it has open (`export STORE -o STORE`). Replacing that file would take
// the input from under the reader, and a store from under its connections (its committed data
// gone with the old inode). stat() of /proc/self/fd/N follows the link to the file and opens
// nothing, so the check itself never disturbs the locks SQLite holds on it.
bool held_by_this_process(const struct stat& target) {
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", error)) {
    struct stat held{};
    if (::stat(entry.path().c_str(), &held) == 0 && held.st_dev == target.st_dev &&
        held.st_ino == target.st_ino)
      return true;
  }
  return false;  // no /proc: nothing to compare with
}

// lstat() of the target: false when nothing is there, true for a regular file (its status in
// `st`); throws for anything else, and for a file this process has open.
bool examine(const std::string& path, struct stat& st) {
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return false;
    io_error(path, "cannot examine the output file", errno);
  }
  if (!S_ISREG(st.st_mode))
    io_error(path,
             fmt::format("refusing to replace it: it is {}; give a regular file, a new name, or '-' for "
                         "standard output",
                         type_name(st.st_mode)));
  if (held_by_this_process(st))
    io_error(path, "refusing to replace it: it is an input of this command; give another name");
  return true;
}

// A stream buffer over a file descriptor, so that `write` can stream any amount of text; it
// keeps the first write(2) error for the message.
class FdBuffer : public std::streambuf {
 public:
  explicit FdBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (error_ == 0) error_ = n < 0 ? errno : EIO;
        return false;
      }
      p += n;
    }
    setp(buffer_, buffer_ + sizeof buffer_);
    return true;
  }

  int fd_;
  int error_ = 0;
  char buffer_[1 << 16];
};

// A name for the temporary in the target's folder: hidden, recognisable, and random, so that
// nobody can plant a file or link under it in advance (O_EXCL refuses one anyway).
std::string temporary_name(const std::string& dir, const std::string& base) {
  static constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  std::random_device device;  // getrandom(2)
  std::string suffix(12, 'x');
  for (auto& c : suffix) c = kAlphabet[device() % (sizeof kAlphabet - 1)];
  // 200 bytes of the name at most: with the suffix, the name stays under NAME_MAX (255).
  return fmt::format("{}.{}.{}.tmp", dir, base.substr(0, 200), suffix);
}

void write_stdout(const std::function<void(std::ostream&)>& write) {
  write(std::cout);
  std::cout.flush();
  if (!std::cout) throw Error(ErrorKind::io, "<stdout>: write failed");
}

}  // namespace

bool check_output_target(const std::string& path) {
  struct stat st {};
  return examine(path, st);
}

void write_output_file(const std::string& path, const std::function<void(std::ostream&)>& write,
                       const OutputFileOptions& options) {
  if (path == "-") return write_stdout(write);
  if (path.empty()) throw Error(ErrorKind::usage, "an empty output file name");
  struct stat target {};
  const bool replacing = examine(path, target);

  const auto slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string temporary;
  Fd fd;
  for (int attempt = 0; !fd; ++attempt) {
    temporary = temporary_name(dir, base);
    // 0666: the umask takes its share, as for any file a program creates.
    fd.reset(::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666));
    if (!fd && (errno != EEXIST || attempt >= 16))
      io_error(path, fmt::format("cannot create a file in {}", dir.empty() ? "." : dir), errno);
  }
  try {
    if (options.mode >= 0) {
      if (::fchmod(fd.get(), static_cast<mode_t>(options.mode)) != 0)
        io_error(temporary, "cannot set its mode", errno);
    } else if (replacing) {
      if (::fchmod(fd.get(), target.st_mode & 07777) != 0) io_error(temporary, "cannot set its mode", errno);
    }
    // As root, a replaced file keeps its owner (root's files stay root's, a user's stay theirs).
    if (replacing && ::geteuid() == 0 && ::fchown(fd.get(), target.st_uid, target.st_gid) != 0)
      io_error(temporary, "cannot set its owner", errno);
    {
      FdBuffer buffer(fd.get());
      std::ostream out(&buffer);
      try {
        write(out);
        out.flush();
      } catch (...) {
        // A writer that gave up because the stream failed: the system's reason, with the path.
        if (buffer.error() != 0) io_error(path, "write failed", buffer.error());
        throw;
      }
      if (!out || buffer.error() != 0) io_error(path, "write failed", buffer.error());
    }
    if (::fsync(fd.get()) != 0) io_error(path, "write failed (fsync)", errno);
    if (fd.close() != 0) io_error(path, "write failed (close)", errno);
    // Again just before the rename: the target may have been swapped for a link or a device
    // meanwhile. (rename(2) itself never follows a link: it would replace the link, not its target.)
    examine(path, target);
    if (::rename(temporary.c_str(), path.c_str()) != 0) io_error(path, "cannot replace it", errno);
  } catch (...) {
    fd.reset();
    ::unlink(temporary.c_str());
    throw;
  }
  // The new name on disk too (power loss); a folder that cannot be synced still holds a complete
  // file under the new name, so a failure here is not an error.
  const Fd dir_fd(::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (dir_fd) (void)::fsync(dir_fd.get());
}

void write_output_file(const std::string& path, std::string_view content, const OutputFileOptions& options) {
  write_output_file(
      path,
      [&](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); },
      options);
}

}  // namespace m2mlat::core
