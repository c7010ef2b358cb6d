// A command-line duration ("5ms", "1.5s", "250us"): core::parse_duration with the flag named in the
// usage error, so that a bad value says which flag it came from.
#pragma once

#include <string>

#include "m2mlat/core/time.hpp"

namespace m2mlat::cli {

// Throws core::Error(usage) "<flag>: <why>". With `empty_is_zero`, "" is Duration{0} (a flag whose
// empty default means "not given").
core::Duration duration_flag(const std::string& flag, const std::string& text, bool empty_is_zero = false);

}  // namespace m2mlat::cli
