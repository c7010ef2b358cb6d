// Strict parsers for request parameters: digits are counted before they are converted, so no
// input can overflow, and JSON is parsed without exceptions so that malformed text is a 400.
#include "m2mlat/net/query.hpp"

#include <fmt/format.h>

#include <limits>
#include <nlohmann/json.hpp>

namespace m2mlat::net {

namespace {

// Shows at most 40 bytes of what the client sent, escaped, so that error bodies stay small.
std::string shown(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f || c == '\'' || c == '\\')
      out += fmt::format("\\x{:02x}", u);
    else
      out += c;
  }
  if (text.size() > 40) out += "...";
  return "'" + out + "'";
}

// Decimal digits only, at most 19 of them; the value must fit in int64.
std::optional<std::int64_t> decimal(std::string_view text) {
  if (text.empty() || text.size() > 19) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
  }
  if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
  return static_cast<std::int64_t>(value);
}

bool valid_text(const std::string& text) {
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
  return true;  // nlohmann's parser has already refused invalid UTF-8
}

}  // namespace

std::int64_t parse_after(std::optional<std::string_view> text, std::string_view name) {
  if (!text) return 0;
  const auto value = decimal(*text);
  if (!value)
    throw RequestError(400, fmt::format("{}={}: not a sequence number (0 to {})", name, shown(*text),
                                        std::numeric_limits<std::int64_t>::max()));
  return *value;
}

std::size_t parse_limit(std::optional<std::string_view> text) {
  if (!text) return kDefaultLimit;
  const auto value = decimal(*text);
  if (!value || *value < 1 || *value > static_cast<std::int64_t>(kMaxLimit))
    throw RequestError(400,
                       fmt::format("limit={}: not a whole number from 1 to {}", shown(*text), kMaxLimit));
  return static_cast<std::size_t>(*value);
}

SessionRequest parse_session_request(std::string_view body) {
  SessionRequest request;
  if (body.find_first_not_of(" \t\r\n") == std::string_view::npos) return request;
  const auto json = nlohmann::json::parse(body.begin(), body.end(), nullptr, false);
  if (json.is_discarded()) throw RequestError(400, "the body is not valid JSON");
  if (!json.is_object()) throw RequestError(400, "the body must be a JSON object");
  for (const auto& [key, value] : json.items()) {
    std::string* field = nullptr;
    if (key == "label")
      field = &request.label;
    else if (key == "scenario")
      field = &request.scenario;
    else
      throw RequestError(400, fmt::format("field {}: unknown (label and scenario are allowed)", shown(key)));
    if (!value.is_string()) throw RequestError(400, fmt::format("field '{}': not a string", key));
    *field = value.get<std::string>();
    if (field->size() > kMaxSessionText)
      throw RequestError(400, fmt::format("field '{}': longer than {} bytes", key, kMaxSessionText));
    if (!valid_text(*field)) throw RequestError(400, fmt::format("field '{}': control characters", key));
  }
  return request;
}

std::optional<std::string_view> parse_bearer(std::string_view header) {
  constexpr std::string_view scheme = "bearer ";
  if (header.size() <= scheme.size()) return std::nullopt;
  for (std::size_t i = 0; i < scheme.size(); ++i) {
    const char c = header[i];
    const char lower = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    if (lower != scheme[i]) return std::nullopt;
  }
  auto token = header.substr(scheme.size());
  while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
  while (!token.empty() && token.back() == ' ') token.remove_suffix(1);
  if (token.empty()) return std::nullopt;
  std::size_t i = 0;
  const auto token_char = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
           c == '.' || c == '_' || c == '~' || c == '+' || c == '/';
  };
  while (i < token.size() && token_char(token[i])) ++i;
  if (i == 0) return std::nullopt;
  while (i < token.size() && token[i] == '=') ++i;
  if (i != token.size()) return std::nullopt;
  return token;
}

}  // namespace m2mlat::net
