// The edge event: one GPIO edge (or an imported/simulated equivalent) on one channel of one node.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::core {

// Values are stored in files and databases: never renumber.
enum class Edge : std::uint8_t { rising = 0, falling = 1 };
std::string_view to_string(Edge edge);
Edge parse_edge(std::string_view text);  // "rising" | "falling"; throws core::Error(usage)

// What a node does in a measurement. The code speaks of cause and effect so that any pair of
// channels on any two nodes can be measured; "operator" and "vehicle" are the teleoperation names.
enum class Role : std::uint8_t { cause = 0, effect = 1, observer = 2 };
std::string_view to_string(Role role);
Role parse_role(std::string_view text);  // cause|operator|remote, effect|vehicle, observer

// Bits of Event::flags. Stored: never renumber.
enum EventFlag : std::uint32_t {
  kFlagSimulated = 1u << 0,       // produced by the simulated rig
  kFlagImported = 1u << 1,        // read from a file, not captured live
  kFlagNoKernelSeqno = 1u << 2,   // the source had no kernel sequence numbers (seqno fields are 0)
  kFlagAfterClockStep = 1u << 3,  // the clock was stepped between this event and the previous one
  kFlagCommanded = 1u << 4,       // an edge m2mlat commanded (pulse generator), not one it observed
};

struct Event {
  std::string node;     // the board's name, e.g. "operator" or "vehicle"
  std::string channel;  // the channel on that node, e.g. "wheel"
  Edge edge = Edge::falling;
  TimePoint time;                // the kernel's timestamp of the edge
  std::uint64_t seqno = 0;       // kernel's event number across the line request (0 = none)
  std::uint64_t line_seqno = 0;  // kernel's event number on this line (0 = none)
  std::uint32_t flags = 0;       // EventFlag bits

  friend bool operator==(const Event&, const Event&) = default;
};

// A channel on a node: "vehicle/wheel". Parses "node/channel" or "node" (channel = default_channel,
// which may be empty to mean "the node's only channel").
struct ChannelRef {
  std::string node;
  std::string channel;
  friend bool operator==(const ChannelRef&, const ChannelRef&) = default;
};
ChannelRef parse_channel_ref(std::string_view text, std::string_view default_channel = "wheel");
std::string to_string(const ChannelRef& ref);

}  // namespace m2mlat::core
