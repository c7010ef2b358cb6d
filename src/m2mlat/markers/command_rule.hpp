// The rule that names the packets carrying commands and says how to recognise the same command on
// both boards: a BPF filter (tcpdump's syntax) and a key taken from each message's payload.
//
// Keys (docs/markers.md):
//   json:NAME           the value of the top-level member NAME of a JSON object payload
//   bytes:OFFSET:LENGTH the payload's bytes [OFFSET, OFFSET + LENGTH), as hex
//   hash                a 64-bit FNV-1a hash of the whole payload, as hex
// A JSON member can also carry the sender's own time in ms (CLOCK_REALTIME), e.g. "stamp": the
// member named by sender_ms.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace m2mlat::markers {

struct KeyRule {
  enum class Kind : std::uint8_t { json, bytes, hash };
  Kind kind = Kind::hash;
  std::string member;      // json: the member's name
  std::size_t offset = 0;  // bytes: first byte
  std::size_t length = 0;  // bytes: how many
};
// Parses "json:stamp", "bytes:0:8", "hash"; throws core::Error(usage) quoting the text.
KeyRule parse_key_rule(std::string_view text);
std::string to_string(const KeyRule& rule);

struct CommandRule {
  std::string filter;     // BPF; empty: every packet
  KeyRule key;
  std::string sender_ms;  // a JSON member holding the sender's time in ms; empty: none
};

// What one message's payload gives under the rule.
struct MessageKey {
  std::optional<std::string> key;           // empty: the payload has no such key
  std::optional<std::int64_t> sender_ns;    // the sender's time, ms converted exactly to ns
};
MessageKey message_key(const CommandRule& rule, std::span<const std::uint8_t> payload);

}  // namespace m2mlat::markers
