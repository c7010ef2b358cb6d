// Printing results: a table on the terminal, or JSON with --json; progress only on a terminal.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace m2mlat::cli {

void print_json(const nlohmann::json& document);  // pretty, to stdout
bool stderr_is_terminal();
// "\r<text>" on stderr when it is a terminal (long work shows progress); nothing otherwise.
void progress(std::string_view text);
void progress_done();              // ends the progress line
// "m2mlat: warning: ..." on stderr. progress() and warn() escape control characters
// (core::printable): their text quotes input.
void warn(std::string_view text);

}  // namespace m2mlat::cli
