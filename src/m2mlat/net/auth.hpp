// The agent's access rule: on a loopback address no token is needed; on any other address the
// agent refuses to start without a bearer token, and every request must then carry it. The token
// comes from a file (--token-file) or the environment (M2MLAT_TOKEN); it is compared in constant
// time so that response timing tells an attacker nothing about how much of a guess was right.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace m2mlat::net {

inline constexpr std::size_t kMinTokenLength = 16;  // characters: guessing must be hopeless

// The token from `token_file` if given (its first line, surrounding blanks removed), else from the
// environment variable M2MLAT_TOKEN if set and not empty, else nothing. Throws core::Error: no_input
// if the file cannot be read; usage if the file is accessible by group or others (secret_file.hpp),
// or the token is shorter than kMinTokenLength or holds characters a Bearer header cannot carry
// (letters, digits and -._~+/= are allowed).
std::optional<std::string> load_token(const std::optional<std::string>& token_file);
// Checks a token's form as load_token does (throws core::Error(usage) naming `origin`).
void check_token(std::string_view token, std::string_view origin);

// Equal contents, in a time that depends only on the lengths (not on where they first differ).
bool tokens_equal(std::string_view a, std::string_view b);

// Whether `host` (an IPv4 or IPv6 literal, brackets allowed, or "localhost") names the loopback
// interface: 127.0.0.0/8, ::1, ::ffff:127.x.x.x. Anything else (0.0.0.0, ::, a name) is not.
bool is_loopback(std::string_view host);

}  // namespace m2mlat::net
