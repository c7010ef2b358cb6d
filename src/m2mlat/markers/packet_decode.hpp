// From a captured frame to the transport segment it carries: the link layer (Ethernet with VLAN
// tags, Linux cooked SLL and SLL2, raw IP, BSD loopback/null), IPv4 or IPv6, then UDP or TCP.
// Anything else (ARP, ICMP, IP fragments, frames cut short by the snapshot length) is no segment.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace m2mlat::markers {

// Whether decode_segment() reads frames of this DLT_* link type.
bool is_supported_link_type(int link_type);
// "EN10MB (Ethernet)", or the number when libpcap has no name for it.
std::string link_type_text(int link_type);

enum class Transport : std::uint8_t { udp, tcp };

// One direction of a conversation: addresses (IPv4 in the first 4 bytes) and ports.
struct Flow {
  std::array<std::uint8_t, 16> source{};
  std::array<std::uint8_t, 16> destination{};
  std::uint16_t source_port = 0;
  std::uint16_t destination_port = 0;
  std::uint8_t ip_version = 4;
  Transport transport = Transport::udp;
  friend bool operator==(const Flow&, const Flow&) = default;
  friend auto operator<=>(const Flow&, const Flow&) = default;
};
std::string to_string(const Flow& flow);  // "udp 10.0.0.1:5000>10.0.0.2:6000"

struct Segment {
  Flow flow;
  std::span<const std::uint8_t> payload;  // the transport's payload (UDP datagram, TCP segment data)
  // TCP only:
  std::uint32_t sequence = 0;  // the first payload byte's sequence number
  bool syn = false;
  bool fin = false;
  bool rst = false;
};

enum class DecodeResult : std::uint8_t {
  segment,    // a UDP or TCP segment
  other,      // a packet of another protocol (not counted as a problem)
  fragment,   // an IP fragment (not reassembled)
  snapped,    // the snapshot length cut the packet's headers or payload
  malformed,  // headers that contradict each other
};

// `frame` is a packet as captured with the given link type; `wire_length` its length on the wire.
DecodeResult decode_segment(int link_type, std::span<const std::uint8_t> frame, std::uint32_t wire_length,
                            Segment& out);

}  // namespace m2mlat::markers
