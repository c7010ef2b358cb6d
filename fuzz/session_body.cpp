// Fuzzes the parser of POST /v1/sessions bodies: any bytes give a request whose label and scenario
// are within the size limit and free of control characters, or a 400.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/net/query.hpp"

namespace {
bool clean(const std::string& text) {
  if (text.size() > m2mlat::net::kMaxSessionText) return false;
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view body(reinterpret_cast<const char*>(data), size);
  try {
    const auto request = m2mlat::net::parse_session_request(body);
    if (!clean(request.label) || !clean(request.scenario)) std::abort();
  } catch (const m2mlat::net::RequestError& e) {
    if (e.status() != 400) std::abort();
  }
  return 0;
}
