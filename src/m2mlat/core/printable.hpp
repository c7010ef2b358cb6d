// Text from input made safe to show on a terminal. Node names, labels, scenario and channel names
// and error messages quoting a file come from files, stores and the network; printed raw, an ESC
// or other control character in them would drive the terminal (move the cursor, rewrite earlier
// lines, set the window title) and a newline would forge output lines. Every place that prints
// such text to the terminal, or into a text report meant to be read there, passes it through
// printable() first. JSON output escapes by its own rules; CSV and JSON Lines files keep the bytes
// as they are (docs/formats.md).
#pragma once

#include <string>
#include <string_view>

namespace m2mlat::core {

// `text` with every control character escaped, C-style: "\n", "\r", "\t", other C0 bytes and DEL
// as "\x1b"; the C1 controls (U+0080..U+009F) and the bidirectional overrides and isolates
// (U+202A..U+202E, U+2066..U+2069, which reorder what follows) as "\u009b"; each byte of invalid
// UTF-8 as "\xff". Everything else, including valid non-ASCII UTF-8 ("µs", "±"), is unchanged.
std::string printable(std::string_view text);

}  // namespace m2mlat::core
