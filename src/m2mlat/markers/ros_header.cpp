#include "m2mlat/markers/ros_header.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::markers {

bool schema_has_header(std::string_view encoding, std::string_view text) {
  if (encoding != "ros2msg") return false;
  // The first line with a field: comments (#...) and blank lines are not fields; constants (TYPE
  // NAME=VALUE) are, and a message beginning with one has no header first.
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos) continue;
    line = line.substr(first);
    const auto space = line.find_first_of(" \t");
    const std::string_view type = line.substr(0, space);
    return type == "std_msgs/Header" || type == "std_msgs/msg/Header" || type == "Header";
  }
  return false;
}

std::int64_t header_stamp_ns(std::string_view cdr, const std::string& where) {
  if (cdr.size() < 12)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: message of {} bytes is too short for a CDR header.stamp (12)", where, cdr.size()));
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(cdr[i]); };
  if (byte(0) != 0x00 || (byte(1) != 0x00 && byte(1) != 0x01))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: CDR encapsulation {:#04x} {:#04x} is not plain CDR (00 00 big-endian, 00 01 "
                                  "little-endian)",
                                  where, byte(0), byte(1)));
  const bool little = byte(1) == 0x01;
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t k = little ? at + 3 - i : at + i;
      v = (v << 8) | byte(k);
    }
    return v;
  };
  const auto sec = static_cast<std::int32_t>(u32(4));
  const std::uint32_t nanosec = u32(8);
  if (nanosec >= 1'000'000'000U)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: header.stamp.nanosec is {} (expected below 10^9): not a header", where, nanosec));
  return static_cast<std::int64_t>(sec) * 1'000'000'000 + static_cast<std::int64_t>(nanosec);
}

}  // namespace m2mlat::markers
