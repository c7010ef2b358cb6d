// Fuzzes the query-parameter parsers (after=, limit=, Last-Event-ID): any bytes either give a value
// in range that prints back to the same digits (leading zeros aside) or a 400, never anything else.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "m2mlat/net/query.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using m2mlat::net::RequestError;
  try {
    const auto after = m2mlat::net::parse_after(text);
    if (after < 0) std::abort();
    const auto digits = text.substr(std::min(text.find_first_not_of('0'), text.size()));
    if (std::to_string(after) != (digits.empty() ? "0" : digits)) std::abort();
  } catch (const RequestError& e) {
    if (e.status() != 400) std::abort();
  }
  try {
    const auto limit = m2mlat::net::parse_limit(text);
    if (limit < 1 || limit > m2mlat::net::kMaxLimit) std::abort();
  } catch (const RequestError& e) {
    if (e.status() != 400) std::abort();
  }
  return 0;
}
