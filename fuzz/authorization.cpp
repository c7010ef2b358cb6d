// Fuzzes the Authorization header parser and the token comparison: a parsed token is a non-empty
// token68 inside the header; the comparison agrees with ==.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/net/auth.hpp"
#include "m2mlat/net/query.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view header(reinterpret_cast<const char*>(data), size);
  if (const auto token = m2mlat::net::parse_bearer(header)) {
    if (token->empty() || token->data() < header.data() ||
        token->data() + token->size() > header.data() + header.size())
      std::abort();
    for (const char c : *token)
      if (c == ' ' || static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e)
        std::abort();
  }
  // Split the input in two and compare the halves both ways.
  const auto a = header.substr(0, size / 2);
  const auto b = header.substr(size / 2);
  if (m2mlat::net::tokens_equal(a, b) != (a == b)) std::abort();
  if (!m2mlat::net::tokens_equal(a, a)) std::abort();
  return 0;
}
