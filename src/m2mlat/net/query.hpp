// The request parsers of the agent API: the query parameters after= and limit=, the SSE resume
// header Last-Event-ID, the JSON body of POST /v1/sessions and the Authorization header. Each takes
// the raw text as it came off the network and either returns a checked value or throws
// RequestError with the HTTP status (400) and a message naming the parameter; none of them trusts
// its input's length, encoding or range.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace m2mlat::net {

// A request the server refuses: the status to answer with and the reason (for the JSON error body).
class RequestError : public std::runtime_error {
 public:
  RequestError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

inline constexpr std::size_t kDefaultLimit = 1000;   // items per page when limit= is absent
inline constexpr std::size_t kMaxLimit = 10000;      // the largest page a client may ask for
inline constexpr std::size_t kMaxSessionText = 256;  // bytes of a session's label or scenario

// A resume point (after=, Last-Event-ID): a decimal integer 0 <= n <= INT64_MAX, digits only (no
// sign, no spaces, at most 19 digits). Absent -> 0. `name` is used in the message.
std::int64_t parse_after(std::optional<std::string_view> text, std::string_view name = "after");
// A page size: a decimal integer 1..kMaxLimit. Absent -> kDefaultLimit.
std::size_t parse_limit(std::optional<std::string_view> text);

// The body of POST /v1/sessions: empty, or a JSON object whose only members are "label" and
// "scenario", both optional strings of at most kMaxSessionText bytes of UTF-8 without control
// characters.
struct SessionRequest {
  std::string label;
  std::string scenario;
  friend bool operator==(const SessionRequest&, const SessionRequest&) = default;
};
SessionRequest parse_session_request(std::string_view body);

// The token of an `Authorization: Bearer <token>` header (the scheme is case-insensitive; the
// token is RFC 6750's token68: letters, digits and -._~+/ followed by any '='). Returns nothing for
// any other header value (absent, another scheme, empty or malformed token): the caller answers 401.
std::optional<std::string_view> parse_bearer(std::string_view header);

}  // namespace m2mlat::net
