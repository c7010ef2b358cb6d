// Writing exports: a buffer that goes to a stream in large blocks, and integer and JSON-string
// formatting without locale or double. Files are written by core::write_output_file.
#pragma once

#include <charconv>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>

namespace m2mlat::formats {

// Collects output text and hands it to the stream about every 1 MiB, so that writing millions of
// lines costs one stream call per block, not per field.
class OutputBuffer {
 public:
  explicit OutputBuffer(std::ostream& out) : out_(out) { text_.reserve(kBlock + 4096); }
  OutputBuffer(const OutputBuffer&) = delete;
  OutputBuffer& operator=(const OutputBuffer&) = delete;

  std::string& text() { return text_; }
  OutputBuffer& operator<<(std::string_view s) {
    text_.append(s);
    return *this;
  }
  OutputBuffer& operator<<(char c) {
    text_.push_back(c);
    return *this;
  }
  template <class Int>
  requires std::is_integral_v<Int> OutputBuffer& integer(Int value) {
    char digits[24];
    const auto [end, ec] = std::to_chars(digits, digits + sizeof digits, value);
    text_.append(digits, end);
    return *this;
  }
  // Call at the end of each record: writes the block out when it is full.
  void end_record() {
    if (text_.size() >= kBlock) flush();
  }
  // Writes out what is left; throws core::Error(io) if the stream failed.
  void flush();

 private:
  static constexpr std::size_t kBlock = std::size_t{1} << 20;
  std::ostream& out_;
  std::string text_;
};

// Appends `s` as a JSON string: quoted, with ", \ and control characters escaped.
void append_json_string(std::string& out, std::string_view s);

}  // namespace m2mlat::formats
