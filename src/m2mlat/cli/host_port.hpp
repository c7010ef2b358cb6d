// A command-line address, "HOST:PORT" or "[V6]:PORT" (`agent --listen`, `mark --to`), split into
// its host and port with the flag named in the usage error.
#pragma once

#include <cstdint>
#include <string>

namespace m2mlat::cli {

struct HostPort {
  std::string host;        // a name or an address; an IPv6 address without its brackets
  std::uint16_t port = 0;  // 0 only where `zero_port_allowed`
};

// Throws core::Error(usage) "<flag> '<text>': use HOST:PORT, e.g. <examples>" when the text has no
// port, an IPv6 address without brackets, or a port that is not 1..5 digits up to 65535 (or is 0 when
// `zero_port_allowed` is false: a listener may take any free port, a sender needs a real one).
HostPort split_host_port(const std::string& flag, const std::string& text, const std::string& examples,
                         bool zero_port_allowed);

}  // namespace m2mlat::cli
