// Input text read whole, and a cursor over its lines.
//
// Every importer reads its whole input before it returns anything, so that a malformed line anywhere
// ends in an exception and leaves the caller with nothing partial (the lean kernel-log import reads
// its file block by block instead: file_lines.hpp). Lines are string_views into one
// buffer (no per-line allocation), which is what lets the importers parse tens of millions of lines
// per second. A UTF-8 byte-order mark and Windows line endings (CRLF) are accepted.
//
// Limits, the same for every format: a line holds at most kMaxLineBytes (a longer one is refused
// with its file and line, while it is read from a pipe, so that an endless stream without newlines
// cannot grow without bound), and a last line without its newline after earlier lines is refused
// as a file cut mid-write (check_input). Only regular files, pipes and standard input are read.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

#include "m2mlat/core/fd.hpp"

namespace m2mlat::formats {

// An input opened for reading: a regular file, a pipe, or standard input ("-", named "<stdin>").
struct OpenedInput {
  core::Fd owned;  // closed with this (never standard input)
  int fd = -1;
  std::string name;         // for messages
  bool stream = false;      // a pipe or standard input: its lines are checked as the data comes
  bool regular = false;     // a regular file (standard input may be one too)
  std::size_t size = 0;     // a regular file's size at opening, bytes (else 0)
};
// Throws core::Error: no_input if the file does not exist, is a directory or a device (/dev/zero
// would never end), io if it cannot be opened.
OpenedInput open_input(const std::string& path);

// The bytes of one input, owned, with the name used in error messages.
class InputText {
 public:
  // Reads the whole file in one go; "-" reads standard input (named "<stdin>" in messages). A pipe
  // and standard input are read with the line limit checked as the data comes (core::Error(data)
  // for a longer line).
  // Throws core::Error: no_input if the file does not exist or is not a regular file or a pipe (a
  // device: /dev/zero would never end), io if it cannot be read.
  static InputText read_file(const std::string& path);
  // Wraps text already in memory (tests, network payloads); `name` appears in error messages.
  static InputText from_string(std::string_view text, std::string name);

  std::string_view text() const { return {data_.get(), size_}; }
  const std::string& name() const { return name_; }

 private:
  InputText(std::unique_ptr<char[]> data, std::size_t size, std::string name)
      : data_(std::move(data)), size_(size), name_(std::move(name)) {}

  std::unique_ptr<char[]> data_;
  std::size_t size_ = 0;
  std::string name_;
};

// The longest line any reader accepts, in bytes without its line end: 64 KiB. The longest line of
// any format m2mlat reads is a few hundred bytes; a longer one is not text of these formats.
inline constexpr std::size_t kMaxLineBytes = 64 * 1024;

// Throws core::Error(data) "<name>:<line>: line is longer than 65536 bytes" for the first line of
// text[from, end) longer than kMaxLineBytes (`from` must be a line's start). Returns the start of
// the last line of the text when it is not longer than the limit (with a stream, where the next
// check can begin). Costs one memrchr of at most a few lines per 64 KiB.
// `lines_before`: lines of the input before `text` (when text is a block of a longer input).
std::size_t check_line_lengths(std::string_view text, std::string_view name, std::size_t from = 0,
                               long lines_before = 0);

// The checks every importer makes before it reads a line: the line lengths, and the last line.
// A last line without a newline, after lines that ended with one, is how a file cut mid-write
// ends (a recorder killed, a copy interrupted, a disk full): "GPIO_16_IRQ:17000" would be read as
// an event at 17000 ns. It is refused with core::Error(data) naming file and line unless it is
// blank. A text of one line without a newline (echo -n, a string in memory) is accepted.
void check_input(std::string_view text, std::string_view name);
// check_input's error for the last line (line number `line`, text `last`) without its newline.
[[noreturn]] void throw_cut_last_line(std::string_view name, long line, std::string_view last);

// Removes a leading UTF-8 byte-order mark (EF BB BF), which spreadsheet programs write.
constexpr std::string_view strip_bom(std::string_view text) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  return text;
}

// Walks the lines of a text: each line is returned without its LF or CRLF terminator. Line numbers
// are 1-based and count every line of the file, blank ones included, so that they match an editor's.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : rest_(strip_bom(text)) {}
  // A block from the middle of an input: a byte-order mark there is text, not a mark.
  struct Continued {};
  LineReader(std::string_view text, Continued) : rest_(text) {}

  // The next line; false at the end. A final line without a newline is still returned (check_input
  // refuses one that looks cut); the empty "line" after a final newline is not.
  bool next(std::string_view& line) {
    if (rest_.empty()) return false;
    const void* nl = std::memchr(rest_.data(), '\n', rest_.size());
    std::size_t length = rest_.size();
    std::size_t consumed = length;
    if (nl != nullptr) {
      length = static_cast<std::size_t>(static_cast<const char*>(nl) - rest_.data());
      consumed = length + 1;
    }
    line = rest_.substr(0, length);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    rest_.remove_prefix(consumed);
    ++line_number_;
    return true;
  }

  // The number of the line last returned by next() (0 before the first call).
  long line_number() const { return line_number_; }

 private:
  std::string_view rest_;
  long line_number_ = 0;
};

// True for a line holding nothing but spaces and tabs (blank lines are skipped by every importer).
constexpr bool is_blank(std::string_view line) {
  for (char c : line)
    if (c != ' ' && c != '\t') return false;
  return true;
}

// An upper bound of the number of lines (newlines + 1), to reserve result vectors in one go.
inline std::size_t count_lines(std::string_view text) {
  std::size_t n = 1;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    const void* nl = std::memchr(p, '\n', static_cast<std::size_t>(end - p));
    if (nl == nullptr) break;
    ++n;
    p = static_cast<const char*>(nl) + 1;
  }
  return n;
}

}  // namespace m2mlat::formats
