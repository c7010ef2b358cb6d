// A line diff for showing what a setup step changes in an existing file: the lines of the longest
// common subsequence are kept (" "), the others removed ("-") or added ("+"). Configuration files
// are short, so the plain O(n*m) table is enough.
#pragma once

#include <string>
#include <string_view>

namespace m2mlat::setup {

// The diff of `before` and `after` as lines "-old", "+new" and " same" (each ending in '\n'),
// after a header "--- <name> (now)" / "+++ <name> (new)". Empty when the texts are equal.
std::string line_diff(std::string_view before, std::string_view after, std::string_view name);

}  // namespace m2mlat::setup
