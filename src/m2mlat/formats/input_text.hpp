// Input text read whole, and a cursor over its lines.
//
// Every importer reads its whole input before it builds anything, so that a malformed line anywhere
// ends in an exception and leaves the caller with nothing partial. Lines are string_views into one
// buffer (no per-line allocation), which is what lets the importers parse tens of millions of lines
// per second. A UTF-8 byte-order mark, Windows line endings (CRLF) and a missing final newline are
// all accepted.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>

namespace m2mlat::formats {

// The bytes of one input, owned, with the name used in error messages.
class InputText {
 public:
  // Reads the whole file in one go; "-" reads standard input (named "<stdin>" in messages).
  // Throws core::Error: no_input if the file does not exist, io if it cannot be read.
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

  // The next line; false at the end. A final line without a newline is still returned; the empty
  // "line" after a final newline is not.
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
