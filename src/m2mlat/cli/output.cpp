// Output helpers shared by the subcommands.
#include "m2mlat/cli/output.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "m2mlat/core/printable.hpp"

namespace m2mlat::cli {

std::string json_text(const nlohmann::json& document) {
  return document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

void print_json(const nlohmann::json& document) { std::cout << json_text(document) << '\n'; }

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

void progress(std::string_view text) {
  if (stderr_is_terminal()) fmt::print(stderr, "\r\x1b[2K{}", core::printable(text));
}

void progress_done() {
  if (stderr_is_terminal()) fmt::print(stderr, "\r\x1b[2K");
}

void warn(std::string_view text) { fmt::print(stderr, "m2mlat: warning: {}\n", core::printable(text)); }

}  // namespace m2mlat::cli
