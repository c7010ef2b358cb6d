// Reading the full-loop rig's result CSV.
#include "m2mlat/formats/full_loop_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::size_t kNoColumn = kFullLoopColumns.size();

std::size_t column_of(std::string_view field) {
  const auto* it = std::find(kFullLoopColumns.begin(), kFullLoopColumns.end(), field);
  return static_cast<std::size_t>(it - kFullLoopColumns.begin());
}

// A number that parse_integer refuses only for its size: an optional '-' and digits.
bool is_integer_text(std::string_view text) {
  if (text.starts_with('-')) text.remove_prefix(1);
  return is_digits(text);
}

}  // namespace

bool looks_like_full_loop_header(std::span<const std::string_view> fields) {
  std::size_t known = 0;
  for (const std::string_view field : fields) known += column_of(field) != kNoColumn ? 1 : 0;
  return known >= 3;
}

FullLoopImport import_full_loop_csv(std::string_view text, std::string_view name) {
  const std::string header_text = fmt::format("{}", fmt::join(kFullLoopColumns, ","));
  LineReader reader(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  do {
    if (!reader.next(line))
      throw_line_error(name, 0, fmt::format("is empty (expected the header '{}')", header_text));
  } while (is_blank(line));

  // The header: each file column -> its FullLoopColumn.
  if (!split_csv(line, fields)) throw_line_error(name, reader.line_number(), "unterminated quote");
  std::vector<std::size_t> file_to_column(fields.size(), kNoColumn);
  std::array<bool, kFullLoopColumns.size()> seen{};
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const std::size_t column = column_of(fields[i]);
    if (column == kNoColumn)
      throw_line_error(name, reader.line_number(),
                       fmt::format("header column {} is {}, which is not one of '{}'", i + 1,
                                   quote_for_message(fields[i]), header_text));
    if (seen[column])
      throw_line_error(name, reader.line_number(),
                       fmt::format("header column {} repeats {}", i + 1, kFullLoopColumns[column]));
    seen[column] = true;
    file_to_column[i] = column;
  }
  for (std::size_t column = 0; column < seen.size(); ++column)
    if (!seen[column])
      throw_line_error(name, reader.line_number(),
                       fmt::format("header lacks the column {} (expected '{}', in any order)",
                                   kFullLoopColumns[column], header_text));

  FullLoopImport result;
  result.rows.reserve(count_lines(text));
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    const long number = reader.line_number();
    if (!split_csv(line, fields)) throw_line_error(name, number, "unterminated quote");
    if (column_of(fields.front()) != kNoColumn)
      throw_line_error(name, number, "the header appears again (were two files joined?)");
    if (fields.size() != file_to_column.size())
      throw_line_error(name, number,
                       fmt::format("expected {} fields ({}), found {}", file_to_column.size(), header_text,
                                   fields.size()));
    FullLoopRow row;
    row.line = number;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string_view field = fields[i];
      if (field.empty()) continue;  // that event's value is missing
      std::int64_t value = 0;
      if (!core::parse_integer(field, value))
        throw_field_error(name, number, kFullLoopColumns[file_to_column[i]], field,
                          is_integer_text(field) ? "is out of range (outside signed 64-bit nanoseconds)"
                                                 : "is not an integer (nanoseconds since the Unix epoch)");
      row.ns[file_to_column[i]] = value;
    }
    result.rows.push_back(row);
  }
  return result;
}

}  // namespace m2mlat::formats
