#include "m2mlat/cli/duration_flag.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::cli {

core::Duration duration_flag(const std::string& flag, const std::string& text, bool empty_is_zero) {
  if (empty_is_zero && text.empty()) return core::Duration{0};
  try {
    return core::parse_duration(text);
  } catch (const core::Error& e) {
    throw core::Error(core::ErrorKind::usage, fmt::format("{}: {}", flag, e.what()));
  }
}

}  // namespace m2mlat::cli
