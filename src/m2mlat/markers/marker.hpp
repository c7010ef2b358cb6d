// A marker: a named point of one command's way through the pipeline, stamped on one board's
// CLOCK_REALTIME (the clock the sensors' edges are on), so that the stages between a cause and its
// effect can be measured on the same synchronised time base as the latency itself.
//
// Packet markers (a command seen in a capture), software markers (datagrams to the agent,
// mark_datagram.hpp) and markers read from ROS 2 bags (bag_markers.hpp) are the same type. The key identifies the command across boards: the same
// command seen on the operator's and the vehicle's board has the same key.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::markers {

// Who took a marker's timestamp. Values are written in files: never rename.
enum class StampSource : std::uint8_t {
  adapter,  // the network adapter's hardware clock, synchronised to the system clock
  host,     // the kernel, when the packet passed the network stack
  file,     // read from a capture file: whoever wrote it (tcpdump, Wireshark) took it; not recorded there
  kernel,      // a software marker's datagram, stamped by the kernel on arrival (SO_TIMESTAMPNS)
  receiver,    // a software marker's datagram, stamped by the receiving program (clock_gettime) when
               // the kernel gave no stamp: later than the arrival by the program's wake-up time
  bag_log,     // a bag's message log time: when the recorder (ros2 bag record) received it
  bag_header,  // a bag's message header.stamp: what the publishing node wrote in the message
};
std::string_view to_string(StampSource source);
// The source of a name written by to_string; nullopt for any other text.
std::optional<StampSource> parse_stamp_source(std::string_view name);

struct Marker {
  std::string node;  // the board ("operator", "vehicle"; the capture's file name when not given)
  std::string name;  // the point in the pipeline ("packet" for a capture)
  core::TimePoint time;  // Clock::realtime, ns
  StampSource source = StampSource::file;
  // The timestamp's uncertainty (ns, k = 1), when known; a packet's capture time has none recorded.
  std::optional<core::Duration> uncertainty;
  std::string key;  // identifies the command across boards (docs/markers.md, "Keys")
  // The sender's own time carried in the command (CLOCK_REALTIME of the sending program), if any.
  std::optional<core::TimePoint> sender_time;
  std::string origin;  // where it was seen: "<capture>#<packet index> <flow>"
};

}  // namespace m2mlat::markers
