// Parsing one JSON Lines record and checking its members' types.
#include "m2mlat/formats/json_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "m2mlat/formats/fields.hpp"

namespace m2mlat::formats {

namespace {
std::string shown(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}
}  // namespace

JsonLine::JsonLine(std::string_view line, std::string_view file, long line_number)
    : file_(file), line_(line_number) {
  // The keys of each object being parsed: a member given twice is refused (nlohmann::json would
  // keep the last, and which one the writer meant is unknowable).
  std::vector<std::vector<std::string>> keys;
  const auto check_keys = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if (event == Event::object_start) {
      keys.emplace_back();
    } else if (event == Event::object_end) {
      keys.pop_back();
    } else if (event == Event::key) {
      const auto& key = parsed.get_ref<const std::string&>();
      auto& seen = keys.back();
      if (std::find(seen.begin(), seen.end(), key) != seen.end())
        throw_line_error(file_, line_, fmt::format("member {} appears twice", quote_for_message(key)));
      seen.push_back(key);
    }
    return true;
  };
  try {
    json_ = nlohmann::json::parse(line, check_keys);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range (1e999)
    // e.what() is "[json.exception.parse_error.101] parse error at line 1, column 5: ..."; the
    // bracketed id and the "line 1" (always 1 here) mean nothing to the user.
    std::string_view what = e.what();
    if (const auto column = what.find("column "); column != std::string_view::npos)
      what.remove_prefix(column);
    else if (const auto close = what.find("] "); what.starts_with("[json.exception") && close != what.npos)
      what.remove_prefix(close + 2);
    throw_line_error(file_, line_, fmt::format("not valid JSON: {}", what));
  }
  if (!json_.is_object()) throw_line_error(file_, line_, "not a JSON object (one object per line)");
}

void JsonLine::expect_format(std::string_view format, std::string_view family, std::string_view older) const {
  const auto found = json_.find("format");
  if (found == json_.end()) missing("format");
  if (!found->is_string()) fail("format", *found, "is not a string");
  const auto& marker = found->get_ref<const std::string&>();
  if (marker == format || (!older.empty() && marker == older)) return;
  if (std::string_view(marker).starts_with(family))
    fail("format", *found, fmt::format("is not supported: this version of m2mlat reads {}", format));
  fail("format", *found, fmt::format("is not {}", format));
}

std::string JsonLine::text(std::string_view key, const nlohmann::json& value) const {
  if (!value.is_string()) fail(key, value, "is not a string");
  const auto& text = value.get_ref<const std::string&>();
  if (text.empty()) fail(key, value, "is empty");
  return text;
}

std::int64_t JsonLine::int64(std::string_view key, const nlohmann::json& value) const {
  if (value.is_number_float())
    fail(key, value, "is not an integer (a JSON float has lost the nanoseconds; write an integer)");
  if (value.is_number_unsigned()) {
    const auto u = value.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      fail(key, value, "is out of range for 64-bit nanoseconds");
    return static_cast<std::int64_t>(u);
  }
  if (value.is_number_integer()) return value.get<std::int64_t>();
  fail(key, value, "is not an integer");
}

std::uint64_t JsonLine::uint64(std::string_view key, const nlohmann::json& value) const {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0)
    return static_cast<std::uint64_t>(value.get<std::int64_t>());
  fail(key, value, "is not a non-negative integer");
}

void JsonLine::fail(std::string_view key, const nlohmann::json& value, std::string_view problem) const {
  throw_line_error(file_, line_,
                   fmt::format("field {}: {} {}", key, quote_for_message(shown(value)), problem));
}

void JsonLine::unknown_member(std::string_view key) const {
  throw_line_error(file_, line_, fmt::format("unknown member {}", quote_for_message(key)));
}

void JsonLine::missing(std::string_view key) const {
  throw_line_error(file_, line_, fmt::format("missing member \"{}\"", key));
}

}  // namespace m2mlat::formats
