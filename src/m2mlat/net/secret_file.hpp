// Secret files: the bearer token and the TLS private key. A secret another user of the machine can
// read is no longer a secret, so such a file is refused rather than used with a warning: the file
// must grant nothing to others, and nothing to its group either, except read on a file owned by
// root (0640: root keeps the secret, a service's group reads it; PostgreSQL's rule for its key).
// Mode 0600 or 0400 always does; `chmod 600 FILE` fixes it. The check is made on the descriptor
// the contents are read from, so it is the file actually used.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace m2mlat::net {

inline constexpr std::size_t kMaxSecretFileBytes = 1 << 20;  // bytes: a token or a PEM key is far smaller

// The whole contents of `path`. Throws core::Error: no_input if it cannot be opened or read; usage
// if it grants others any permission, or its group more than read on a file of root's (the message
// gives the mode and `chmod 600`), or is larger than kMaxSecretFileBytes. `what` names the file's role in
// messages (e.g. "--token-file").
std::string read_secret_file(const std::string& path, std::string_view what);

}  // namespace m2mlat::net
