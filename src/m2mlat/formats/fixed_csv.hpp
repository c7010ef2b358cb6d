// A CSV file with a fixed header, as the reference rig writes them: the header is checked name by
// name, then every row must have exactly as many fields. Blank lines are skipped anywhere (files
// often end with some), a BOM and CRLF line ends are accepted, and a second copy of the header (two
// files joined with cat) is reported as such rather than as a bad number.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

class FixedCsv {
 public:
  // Reads up to and including the header. Throws core::Error(data) if the input is empty, or if
  // its first line is not exactly `columns` ("missing header" when it looks like data).
  FixedCsv(std::string_view text, std::string_view name, std::span<const std::string_view> columns);

  // Moves to the next data row; false at the end. Throws on a wrong number of fields or a repeated
  // header.
  bool next();

  long line() const { return reader_.line_number(); }
  std::string_view text(std::size_t column) const { return fields_[column]; }

  // The field of `column` read as ..., or core::Error(data) naming file, line and column name.
  std::int64_t int64(std::size_t column) const {
    return require_int64(name_, line(), columns_[column], fields_[column]);
  }
  std::int64_t nanoseconds(std::size_t column) const {
    return require_nanoseconds(name_, line(), columns_[column], fields_[column]);
  }
  std::int64_t decimal_seconds(std::size_t column) const {
    return require_decimal_seconds(name_, line(), columns_[column], fields_[column]);
  }
  std::int64_t decimal_ms(std::size_t column) const {
    return require_decimal_ms(name_, line(), columns_[column], fields_[column]);
  }
  // seconds * 10^9 + nanoseconds of two columns, with an error if it overflows int64.
  std::int64_t epoch_ns(std::size_t seconds_column, std::size_t nanoseconds_column) const;
  // Throws unless the field is empty (the rig's files have an unnamed empty column).
  void expect_empty(std::size_t column) const;

  // Throws core::Error(data) "<file>:<line>: <what>" for the current row.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  bool is_header_again() const;

  LineReader reader_;
  std::string name_;
  std::span<const std::string_view> columns_;
  std::string header_text_;  // "Line,Seconds,Nanoseconds", for messages
  std::vector<std::string_view> fields_;
};

// Joins column names with commas, as a header line.
std::string join_columns(std::span<const std::string_view> columns);

}  // namespace m2mlat::formats
