// Header checks and row splitting for the reference rig's CSV files.
#include "m2mlat/formats/fixed_csv.hpp"

#include <fmt/format.h>

#include "m2mlat/core/time.hpp"

namespace m2mlat::formats {

std::string join_columns(std::span<const std::string_view> columns) {
  std::string joined;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) joined.push_back(',');
    joined.append(columns[i]);
  }
  return joined;
}

FixedCsv::FixedCsv(std::string_view text, std::string_view name, std::span<const std::string_view> columns)
    : reader_(text), name_(name), columns_(columns), header_text_(join_columns(columns)) {
  fields_.reserve(columns.size() + 1);
  std::string_view line;
  bool found = false;
  while (reader_.next(line)) {
    if (!is_blank(line)) {
      found = true;
      break;
    }
  }
  if (!found) throw_line_error(name_, 0, fmt::format("is empty (expected the header '{}')", header_text_));
  if (!split_csv(line, fields_)) fail("unterminated quote");
  bool same = fields_.size() == columns_.size();
  for (std::size_t i = 0; same && i < columns_.size(); ++i) same = fields_[i] == columns_[i];
  if (same) return;
  std::int64_t number = 0;
  if (!fields_.empty() && core::parse_seconds(fields_[0], number))
    fail(fmt::format("missing header: the file starts with data; expected the header '{}'", header_text_));
  fail(fmt::format("header is {}, expected '{}'", quote_for_message(line), header_text_));
}

bool FixedCsv::next() {
  std::string_view line;
  do {
    if (!reader_.next(line)) return false;
  } while (is_blank(line));
  if (!split_csv(line, fields_)) fail("unterminated quote");
  if (is_header_again()) fail("the header appears again (were two files joined?)");
  if (fields_.size() != columns_.size())
    fail(fmt::format("expected {} fields ({}), found {}", columns_.size(), header_text_, fields_.size()));
  return true;
}

bool FixedCsv::is_header_again() const {
  return !fields_.empty() && fields_[0] == columns_[0] && !columns_[0].empty();
}

std::int64_t FixedCsv::epoch_ns(std::size_t seconds_column, std::size_t nanoseconds_column) const {
  const std::int64_t seconds = int64(seconds_column);
  const std::int64_t nanoseconds = this->nanoseconds(nanoseconds_column);
  std::int64_t ns = 0;
  if (!combine_seconds(seconds, nanoseconds, ns))
    throw_field_error(name_, line(), columns_[seconds_column], fields_[seconds_column],
                      "is out of range (the time overflows 64-bit nanoseconds)");
  return ns;
}

void FixedCsv::expect_empty(std::size_t column) const {
  if (!fields_[column].empty())
    throw_field_error(name_, line(), fmt::format("{} (unnamed)", column + 1), fields_[column],
                      "should be empty");
}

void FixedCsv::fail(const std::string& what) const { throw_line_error(name_, line(), what); }

}  // namespace m2mlat::formats
