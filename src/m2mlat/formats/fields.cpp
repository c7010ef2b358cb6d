// CSV splitting and quoting, and the error messages of every importer.
#include "m2mlat/formats/fields.hpp"

#include <fmt/format.h>

#include <cstring>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::formats {

bool split_csv(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  // The usual case, no quotes: one pass over the characters (fields are short, so a plain loop
  // beats a memchr call per field). A quote sends the line to the general loop below.
  std::size_t start = 0;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == ',') {
      fields.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    } else if (c == '"') {
      quoted = true;
      break;
    }
  }
  if (!quoted) {
    fields.push_back(trim(line.substr(start)));
    return true;
  }
  fields.clear();
  std::size_t i = 0;
  for (;;) {
    const std::size_t field_start = i;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i < line.size() && line[i] == '"') {
      ++i;
      for (;;) {  // inside quotes: "" is a quote, a lone " ends the field
        if (i >= line.size()) return false;
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        ++i;
      }
    }
    while (i < line.size() && line[i] != ',') ++i;
    fields.push_back(trim(line.substr(field_start, i - field_start)));
    if (i >= line.size()) return true;
    ++i;  // the comma
  }
}

std::string field_text(std::string_view field) {
  if (field.size() < 2 || field.front() != '"' || field.back() != '"') return std::string(field);
  field = field.substr(1, field.size() - 2);
  std::string text;
  text.reserve(field.size());
  for (std::size_t i = 0; i < field.size(); ++i) {
    text.push_back(field[i]);
    if (field[i] == '"' && i + 1 < field.size() && field[i + 1] == '"') ++i;
  }
  return text;
}

bool needs_csv_quotes(std::string_view text) {
  for (char c : text)
    if (c == ',' || c == '"') return true;
  // Spaces at either end would be trimmed on reading, and a leading '#' would read as a comment.
  return !text.empty() && (text.front() == ' ' || text.front() == '\t' || text.front() == '#' ||
                           text.back() == ' ' || text.back() == '\t');
}

void append_csv_field(std::string& out, std::string_view text) {
  if (!needs_csv_quotes(text)) {
    out.append(text);
    return;
  }
  out.push_back('"');
  for (char c : text) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
}

std::string quote_for_message(std::string_view text) {
  constexpr std::size_t kMax = 60;  // bytes of the field shown; a longer one ends in "..."
  return fmt::format("'{}{}'", core::printable(text.substr(0, kMax)), text.size() > kMax ? "..." : "");
}

void throw_field_error(std::string_view file, long line, std::string_view field, std::string_view text,
                       std::string_view problem) {
  throw_line_error(file, line, fmt::format("field {}: {} {}", field, quote_for_message(text), problem));
}

std::int64_t require_decimal_seconds(std::string_view file, long line, std::string_view field,
                                     std::string_view text) {
  std::int64_t ns = 0;
  if (!core::parse_seconds(text, ns))
    throw_field_error(file, line, field, text, "is not a decimal number of seconds (at most 9 decimals)");
  return ns;
}

std::int64_t require_decimal_ms(std::string_view file, long line, std::string_view field,
                                std::string_view text) {
  std::int64_t ns = 0;
  if (!core::parse_ms(text, ns))
    throw_field_error(file, line, field, text,
                      "is not a decimal number of milliseconds (at most 6 decimals)");
  return ns;
}

void throw_line_error(std::string_view file, long line, const std::string& what) {
  core::throw_data_error(core::Location{std::string(file), line}, what);
}

}  // namespace m2mlat::formats
