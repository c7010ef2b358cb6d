// The std_msgs/Header at the start of a ROS 2 message: whether a message type has one (from its
// schema's definition), and its stamp read from the message's CDR bytes.
//
// CDR as ROS 2 writes it (rmw with Fast DDS / Cyclone DDS): a 4-byte encapsulation header (0x00 0x00:
// big-endian CDR, 0x00 0x01: little-endian CDR; then two bytes of options), then the fields aligned
// to their size from the end of that header. A message whose first field is `std_msgs/Header header`
// begins with builtin_interfaces/Time stamp: int32 sec at bytes 4..7, uint32 nanosec at 8..11.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace m2mlat::markers {

// True when the schema (encoding "ros2msg": the .msg text, its dependencies after it) has a first
// field of type std_msgs/Header (written "std_msgs/Header", "std_msgs/msg/Header" or "Header").
bool schema_has_header(std::string_view schema_encoding, std::string_view definition);

// header.stamp in ns since the epoch (sec * 10^9 + nanosec). Throws core::Error(data) naming `where`
// for a message too short, an encapsulation other than plain CDR, or nanosec >= 10^9.
std::int64_t header_stamp_ns(std::string_view cdr, const std::string& where);

}  // namespace m2mlat::markers
