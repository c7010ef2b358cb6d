// Reading a whole input file into memory in one go (regular files: one read(2) of the size fstat(2)
// reports; pipes and standard input: growing blocks).
#include "m2mlat/formats/input_text.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/formats/fields.hpp"

namespace m2mlat::formats {

namespace {

[[noreturn]] void throw_io(const std::string& name, const char* what, int err) {
  throw core::Error(core::ErrorKind::io,
                    fmt::format("{}: {}: {}", name, what, std::generic_category().message(err)));
}

}  // namespace

OpenedInput open_input(const std::string& path) {
  const bool is_stdin = path == "-";
  OpenedInput in;
  in.name = is_stdin ? "<stdin>" : path;
  // Closed when the read ends, whichever way it ends; standard input is never closed.
  in.owned = core::Fd(is_stdin ? -1 : ::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  in.fd = is_stdin ? 0 : in.owned.get();
  const std::string& name = in.name;
  if (in.fd < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR)
      throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such file", name));
    throw_io(name, "cannot open", err);
  }

  struct stat st {};
  if (::fstat(in.fd, &st) != 0) throw_io(name, "cannot stat", errno);
  if (S_ISDIR(st.st_mode))
    throw core::Error(core::ErrorKind::no_input, fmt::format("{}: is a directory, not a file", name));
  // A named device is no input file: /dev/zero and /dev/urandom never end. Standard input is
  // whatever the caller made it (a pipe, a terminal, /dev/null) and is read with the line limit.
  in.stream = is_stdin || S_ISFIFO(st.st_mode);
  if (!S_ISREG(st.st_mode) && !in.stream)
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{}: is not a regular file or a pipe (a device or a socket)", name));
  in.regular = S_ISREG(st.st_mode);
  in.size = in.regular ? static_cast<std::size_t>(st.st_size) : 0;
  return in;
}

InputText InputText::read_file(const std::string& path) {
  const OpenedInput in = open_input(path);
  const int fd = in.fd;
  const std::string& name = in.name;
  const bool stream = in.stream;
  // A regular file's size is known: read it into a buffer of exactly that size (plus one byte to
  // notice a file that grew meanwhile). Otherwise start with 1 MiB and double.
  std::size_t capacity = in.regular ? in.size + 1 : std::size_t{1} << 20;
  auto buffer = std::make_unique_for_overwrite<char[]>(capacity);
  std::size_t size = 0;
  std::size_t line_start = 0;  // a stream's lines before this one are checked
  for (;;) {
    if (size == capacity) {
      const std::size_t grown = capacity * 2;
      auto bigger = std::make_unique_for_overwrite<char[]>(grown);
      std::memcpy(bigger.get(), buffer.get(), size);
      buffer = std::move(bigger);
      capacity = grown;
    }
    const ssize_t got = ::read(fd, buffer.get() + size, capacity - size);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw_io(name, "cannot read", errno);
    }
    if (got == 0) break;
    size += static_cast<std::size_t>(got);
    if (stream) line_start = check_line_lengths({buffer.get(), size}, name, line_start);
  }
  return InputText(std::move(buffer), size, name);
}

std::size_t check_line_lengths(std::string_view text, std::string_view name, std::size_t from,
                               long lines_before) {
  // Any kMaxLineBytes + 1 bytes from a line's start hold a newline unless that line is too long;
  // the last newline among them is the start of the next line to look from.
  while (text.size() - from > kMaxLineBytes) {
    const void* nl = ::memrchr(text.data() + from, '\n', kMaxLineBytes + 1);
    if (nl == nullptr) {
      const auto line =
          1 + lines_before + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(from), '\n');
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}:{}: line is longer than {} bytes (no reader takes longer lines)",
                                    name, line, kMaxLineBytes));
    }
    from = static_cast<std::size_t>(static_cast<const char*>(nl) - text.data()) + 1;
  }
  return from;
}

void check_input(std::string_view text, std::string_view name) {
  check_line_lengths(text, name);
  if (text.empty() || text.back() == '\n') return;
  const auto last_nl = text.rfind('\n');
  if (last_nl == std::string_view::npos) return;  // one line: nothing says it was cut
  const std::string_view last = text.substr(last_nl + 1);
  if (is_blank(last) || last == "\r") return;
  throw_cut_last_line(name, 1 + std::count(text.begin(), text.end(), '\n'), last);
}

void throw_cut_last_line(std::string_view name, long line, std::string_view last) {
  throw core::Error(core::ErrorKind::data,
                    fmt::format("{}:{}: the last line does not end with a newline: the file looks cut "
                                "mid-write (if the line {} is complete, add the newline)",
                                name, line, quote_for_message(last)));
}

InputText InputText::from_string(std::string_view text, std::string name) {
  auto buffer = std::make_unique_for_overwrite<char[]>(text.size() + 1);
  std::memcpy(buffer.get(), text.data(), text.size());
  return InputText(std::move(buffer), text.size(), std::move(name));
}

}  // namespace m2mlat::formats
