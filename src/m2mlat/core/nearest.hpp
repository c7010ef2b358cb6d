// The name a user most likely meant: "did you mean" for subcommands, options, scenarios, nodes and
// channels.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace m2mlat::core {

// The candidate nearest to `word` by edit distance, letter case ignored, when it is near enough to
// be a slip (at most max(1, |word| / 3) edits, or a prefix of 3 letters or more); nullopt else, or
// when `word` is itself a candidate.
std::optional<std::string> nearest(std::string_view word, std::span<const std::string> candidates);

// " (did you mean 'x'?)" for nearest's answer, or "" when there is none.
std::string did_you_mean(std::string_view word, std::span<const std::string> candidates);

}  // namespace m2mlat::core
