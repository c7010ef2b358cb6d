// Checks of the names setup writes into paths, unit names and configuration files: a node name
// becomes /etc/m2mlat/<node>.toml and m2mlat-agent@<node>.service, so it must be a plain word.
#pragma once

#include <string_view>

namespace m2mlat::setup {

// Letters, digits, '_', '-' and '.', not starting with '-' or '.', 1..64 characters; else
// core::Error(usage) naming the option.
void check_name(std::string_view option, std::string_view value);
// A value written inside a TOML or environment line: printable, no quotes, backslashes or newlines.
void check_value(std::string_view option, std::string_view value);

}  // namespace m2mlat::setup
