// One JSON Lines record and its members, with errors naming file, line and member.
//
// Integers are taken only from JSON integers: nlohmann::json keeps those exactly as int64/uint64,
// while a JSON number with a fraction or exponent becomes a double and has lost nanoseconds.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace m2mlat::formats {

class JsonLine {
 public:
  // Parses the line; throws core::Error(data) "<file>:<line>: ..." unless it is one JSON object
  // with no member given twice (in it or in any object inside it).
  JsonLine(std::string_view line, std::string_view file, long line_number);

  const nlohmann::json& object() const { return json_; }

  // Requires the member "format" to be `format`; a marker of the same family with another version
  // is "not supported", anything else "not a ... record".
  // `older`, if not empty: an earlier version of the format that is still read.
  void expect_format(std::string_view format, std::string_view family, std::string_view older = {}) const;

  // The member as a non-empty string, an int64 or a uint64 (JSON integers only), or an error.
  std::string text(std::string_view key, const nlohmann::json& value) const;
  std::int64_t int64(std::string_view key, const nlohmann::json& value) const;
  std::uint64_t uint64(std::string_view key, const nlohmann::json& value) const;

  // Throws core::Error(data) "<file>:<line>: field <key>: <value> <problem>".
  [[noreturn]] void fail(std::string_view key, const nlohmann::json& value, std::string_view problem) const;
  [[noreturn]] void unknown_member(std::string_view key) const;
  [[noreturn]] void missing(std::string_view key) const;

 private:
  std::string_view file_;
  long line_;
  nlohmann::json json_;
};

}  // namespace m2mlat::formats
