// The lines of a file read block by block: the same lines, line numbers and refusals as
// InputText::read_file + check_input + LineReader, without holding the whole file in memory.
//
// A kernel log of 10^7 lines is ~480 MB; read whole, the two logs of `m2mlat stats --cause-file
// --effect-file` were two thirds of its peak memory, and filling fresh pages cost more time than
// reading them. Here one buffer of kBlockBytes is read into again and again (it stays in the
// cache), holding whole lines plus the start of the next one.
//
// The refusals of check_input come before any error of the lines' content, as when the whole file
// was checked first: a reader that finds a bad line calls read_to_end() before it reports it, so that
// a line too long or a cut last line anywhere in the file is the error reported instead.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

class FileLines {
 public:
  // The bytes read at a time: 1 MiB, well above kMaxLineBytes (a block always holds a whole line).
  static constexpr std::size_t kBlockBytes = std::size_t{1} << 20;

  // Opens the file (open_input: "-" is standard input). Throws core::Error as open_input does.
  explicit FileLines(const std::string& path, std::size_t block_bytes = kBlockBytes);

  // As LineReader::next: the next line without its LF or CRLF; false at the end. The view is valid
  // until the next call. Throws core::Error(data) naming file and line for a line longer than
  // kMaxLineBytes and, at the end, for a last line cut mid-write (check_input), core::Error(io) when
  // the file cannot be read.
  bool next(std::string_view& line);
  // The number of the line last returned by next() (0 before the first call).
  long line_number() const { return lines_before_ + reader_.line_number(); }
  // Reads the rest of the file, making check_input's checks (used before reporting a bad line).
  void read_to_end();

  const std::string& name() const { return input_.name; }
  // The file's size when opened (regular files; 0 for a pipe): for reserving, bytes.
  std::size_t size_hint() const { return input_.size; }

 private:
  bool refill();

  OpenedInput input_;
  std::unique_ptr<char[]> buffer_;
  std::size_t capacity_ = 0;
  std::size_t used_ = 0;   // bytes in buffer_
  std::size_t taken_ = 0;  // of which handed to reader_ (whole lines)
  bool eof_ = false;
  bool first_block_ = true;
  long lines_before_ = 0;  // lines of the blocks before reader_'s
  LineReader reader_{std::string_view{}};
};

}  // namespace m2mlat::formats
