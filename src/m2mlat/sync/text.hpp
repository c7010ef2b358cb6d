// Small text helpers shared by the parsers of chronyc and pmc output: lines, fields and quoting.
// Their numbers are parsed whole by core/number.hpp, so that "12x" is an error and not 12.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace m2mlat::sync::text {

std::string_view trim(std::string_view s);  // without spaces, tabs, \r and \n at either end
// The lines of a text (without their '\n'); a final line without '\n' counts.
std::vector<std::string_view> lines(std::string_view text);
// Splits at every `sep` (no quoting: chronyc's CSV never quotes).
std::vector<std::string_view> split(std::string_view s, char sep);
// Splits at runs of spaces and tabs; no empty fields.
std::vector<std::string_view> words(std::string_view s);

// The text quoted for an error message, cut to 60 characters.
std::string quoted(std::string_view s);

}  // namespace m2mlat::sync::text
