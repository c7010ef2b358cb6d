// Token loading, constant-time comparison and the loopback test.
#include "m2mlat/net/auth.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <cstdlib>

#include "m2mlat/core/error.hpp"
#include "m2mlat/net/secret_file.hpp"

namespace m2mlat::net {

void check_token(std::string_view token, std::string_view origin) {
  if (token.size() < kMinTokenLength)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("{}: the token is {} characters; use at least {} (e.g. openssl rand -hex 32)", origin,
                    token.size(), kMinTokenLength));
  for (const char c : token) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                    c == '.' || c == '_' || c == '~' || c == '+' || c == '/' || c == '=';
    if (!ok)
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: the token may hold only letters, digits and -._~+/=", origin));
  }
}

std::optional<std::string> load_token(const std::optional<std::string>& token_file) {
  std::string token;
  std::string origin;
  if (token_file) {
    const auto text = read_secret_file(*token_file, "--token-file");
    token = text.substr(0, text.find('\n'));
    origin = *token_file;
  } else if (const char* env = std::getenv("M2MLAT_TOKEN"); env != nullptr && *env != '\0') {
    token = env;
    origin = "M2MLAT_TOKEN";
  } else {
    return std::nullopt;
  }
  const auto first = token.find_first_not_of(" \t\r\n");
  const auto last = token.find_last_not_of(" \t\r\n");
  token = first == std::string::npos ? std::string() : token.substr(first, last - first + 1);
  check_token(token, origin);
  return token;
}

bool tokens_equal(std::string_view a, std::string_view b) {
  // Every byte of the longer one is visited and folded into `diff`; no early exit.
  const std::size_t n = a.size() > b.size() ? a.size() : b.size();
  unsigned diff = a.size() == b.size() ? 0u : 1u;
  for (std::size_t i = 0; i < n; ++i) {
    const auto x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0u;
    const auto y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0u;
    diff |= x ^ y;
  }
  // Keep the compiler from turning the loop into an early-exit comparison.
  volatile unsigned result = diff;
  return result == 0;
}

bool is_loopback(std::string_view host) {
  if (host == "localhost") return true;
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string text(host);
  in_addr v4{};
  if (::inet_pton(AF_INET, text.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (::inet_pton(AF_INET6, text.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
  }
  return false;
}

}  // namespace m2mlat::net
