// Printing results: a table on the terminal, or JSON with --json; progress only on a terminal.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace m2mlat::cli {

// Pretty JSON text. Names from input may hold bytes that are not UTF-8 (a node name, a file
// name): each is written as U+FFFD instead of failing the whole document.
std::string json_text(const nlohmann::json& document);
void print_json(const nlohmann::json& document);  // json_text, to stdout
bool stderr_is_terminal();
// "\r<text>" on stderr when it is a terminal (long work shows progress); nothing otherwise.
void progress(std::string_view text);
void progress_done();              // ends the progress line
// "m2mlat: warning: ..." on stderr. progress() and warn() escape control characters
// (core::printable): their text quotes input.
void warn(std::string_view text);

}  // namespace m2mlat::cli
