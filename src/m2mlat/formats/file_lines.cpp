// Reading a file's lines block by block (file_lines.hpp).
#include "m2mlat/formats/file_lines.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats {

FileLines::FileLines(const std::string& path, std::size_t block_bytes)
    : input_(open_input(path)),
      buffer_(std::make_unique_for_overwrite<char[]>(std::max(block_bytes, 2 * (kMaxLineBytes + 1)))),
      capacity_(std::max(block_bytes, 2 * (kMaxLineBytes + 1))) {}

bool FileLines::next(std::string_view& line) {
  for (;;) {
    if (reader_.next(line)) return true;
    if (!refill()) return false;
  }
}

void FileLines::read_to_end() {
  std::string_view line;
  while (next(line)) {
  }
}

// Hands the next whole lines to reader_: keeps the start of a line the last block cut, reads until
// the buffer holds a newline (or the file ends), and checks the lines as check_input does.
bool FileLines::refill() {
  lines_before_ += reader_.line_number();
  reader_ = LineReader(std::string_view{}, LineReader::Continued{});
  std::memmove(buffer_.get(), buffer_.get() + taken_, used_ - taken_);
  used_ -= taken_;
  taken_ = 0;
  for (;;) {
    // Lines longer than the limit, counted from this block's first line (a line cut by the end of
    // the buffer is checked again, whole, with the next block).
    check_line_lengths({buffer_.get(), used_}, input_.name, 0, lines_before_);
    const void* nl = used_ == 0 ? nullptr : ::memrchr(buffer_.get(), '\n', used_);
    if (nl != nullptr || eof_) {
      std::size_t end = used_;  // at the end of the file: the last line, without its newline
      if (nl != nullptr) end = static_cast<std::size_t>(static_cast<const char*>(nl) - buffer_.get()) + 1;
      if (end == 0) return false;
      std::string_view block(buffer_.get(), end);
      if (nl == nullptr && lines_before_ > 0) {
        // check_input: a last line without a newline after lines that had one looks cut mid-write.
        if (!is_blank(block) && block != "\r") throw_cut_last_line(input_.name, lines_before_ + 1, block);
      }
      reader_ = first_block_ ? LineReader(block) : LineReader(block, LineReader::Continued{});
      first_block_ = false;
      taken_ = end;
      return true;
    }
    // No whole line yet: read more (the buffer holds more than a longest line, which check_line_lengths
    // refused above, so there is room).
    const ssize_t got = ::read(input_.fd, buffer_.get() + used_, capacity_ - used_);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot read: {}", input_.name,
                                                         std::generic_category().message(errno)));
    }
    if (got == 0)
      eof_ = true;
    else
      used_ += static_cast<std::size_t>(got);
  }
}

}  // namespace m2mlat::formats
