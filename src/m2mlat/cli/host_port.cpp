#include "m2mlat/cli/host_port.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"

namespace m2mlat::cli {

HostPort split_host_port(const std::string& flag, const std::string& text, const std::string& examples,
                         bool zero_port_allowed) {
  const auto bad = [&] {
    return core::Error(core::ErrorKind::usage, fmt::format("{} '{}': use HOST:PORT, e.g. {}", flag, text, examples));
  };
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) throw bad();
  HostPort out;
  out.host = text.substr(0, colon);
  if (out.host.front() == '[') {
    if (out.host.back() != ']' || out.host.size() < 3) throw bad();
    out.host = out.host.substr(1, out.host.size() - 2);
  } else if (out.host.find(':') != std::string::npos) {
    throw bad();  // an IPv6 address needs brackets
  }
  const auto port_text = text.substr(colon + 1);  // digits only, at most 5 of them
  if (port_text.size() > 5 || !core::parse_integer(port_text, out.port)) throw bad();
  if (out.port == 0 && !zero_port_allowed) throw bad();
  return out;
}

}  // namespace m2mlat::cli
