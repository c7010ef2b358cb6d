// Checks of names and values used by setup (names.hpp).
#include "m2mlat/setup/names.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::setup {

void check_name(std::string_view option, std::string_view value) {
  const auto bad = [&](std::string_view why) {
    throw core::Error(core::ErrorKind::usage, fmt::format("{} '{}': {}", option, value, why));
  };
  if (value.empty() || value.size() > 64) bad("use 1 to 64 characters");
  if (value.front() == '-' || value.front() == '.') bad("must not start with '-' or '.'");
  for (char c : value) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) bad("use letters, digits, '_', '-' and '.' only");
  }
}

void check_value(std::string_view option, std::string_view value) {
  if (value.empty()) throw core::Error(core::ErrorKind::usage, fmt::format("{}: must not be empty", option));
  for (char c : value)
    if (c == '"' || c == '\\' || c == '\'' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw core::Error(
          core::ErrorKind::usage,
          fmt::format("{} '{}': quotes, backslashes and control characters are not allowed", option, value));
}

}  // namespace m2mlat::setup
