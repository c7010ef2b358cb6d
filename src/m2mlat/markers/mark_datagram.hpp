// The software marker's datagram, `m2mlat-mark/1` (docs/markers.md, "Software markers"): one line of
// text a program sends to the agent's marker port to say "my command passed this point now":
//
//   m2mlat-mark/1 NAME [key=KEY] [t=SENDER_NS]
//
// NAME is the point in the pipeline, KEY identifies the command on every board (the same value the
// packets' key rule or another program's marker gives it), SENDER_NS is the sender's own
// CLOCK_REALTIME when it made the mark (int64 ns). Fields are separated by one or more spaces; a
// final "\n" (or "\r\n") is allowed. Parsed here and written here only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace m2mlat::markers {

inline constexpr std::string_view kMarkFormat = "m2mlat-mark/1";
// The largest datagram read (bytes): a mark is one short line; a longer one is refused, not cut.
inline constexpr std::size_t kMarkMaxBytes = 512;
inline constexpr std::size_t kMarkMaxName = 64;   // characters of NAME
inline constexpr std::size_t kMarkMaxKey = 256;   // characters of KEY

struct MarkDatagram {
  std::string name;
  std::string key;  // empty: none given
  std::optional<std::int64_t> sender_ns;  // CLOCK_REALTIME ns of the sender, if given
  friend bool operator==(const MarkDatagram&, const MarkDatagram&) = default;
};

// What parsing gives: the datagram, or why it was refused. `reason` is one of a few fixed words
// (counted per reason in the agent's status and metrics), `detail` says what exactly was wrong.
struct MarkParse {
  std::optional<MarkDatagram> mark;
  std::string_view reason;  // "format", "name", "key", "time", "field", "size"; empty when parsed
  std::string detail;
};

// The reasons parse_mark can give, in the order status and metrics list them.
inline constexpr std::string_view kMarkReasons[] = {"format", "name", "key", "time", "field", "size"};

// NAME: 1 to kMarkMaxName characters of letters, digits and _ . : / -  (a ROS topic fits).
bool valid_mark_name(std::string_view name);
// KEY: 1 to kMarkMaxKey printable ASCII characters other than space.
bool valid_mark_key(std::string_view key);

MarkParse parse_mark(std::string_view datagram);
// The datagram's text (with a final "\n"). Throws core::Error(usage) for an invalid name or key.
std::string format_mark(const MarkDatagram& mark);

}  // namespace m2mlat::markers
