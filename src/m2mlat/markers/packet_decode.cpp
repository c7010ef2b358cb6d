#include "m2mlat/markers/packet_decode.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <pcap/pcap.h>

#include <algorithm>

namespace m2mlat::markers {

namespace {

using Bytes = std::span<const std::uint8_t>;

std::uint16_t be16(Bytes b, std::size_t at) {
  return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}
std::uint32_t be32(Bytes b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) |
         std::uint32_t{b[at + 3]};
}

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherIpv6 = 0x86DD;
constexpr std::uint16_t kEtherVlan = 0x8100;
constexpr std::uint16_t kEtherQinQ = 0x88A8;
constexpr std::uint8_t kProtoTcp = 6;
constexpr std::uint8_t kProtoUdp = 17;

// The IP packet of the frame, or nullopt for a frame of another protocol.
std::optional<Bytes> ip_packet(int link_type, Bytes frame, DecodeResult& why) {
  why = DecodeResult::snapped;
  std::uint16_t ethertype = 0;
  std::size_t offset = 0;
  switch (link_type) {
    case DLT_EN10MB:
      if (frame.size() < 14) return std::nullopt;
      ethertype = be16(frame, 12);
      offset = 14;
      while (ethertype == kEtherVlan || ethertype == kEtherQinQ) {  // 802.1Q tags: 4 bytes each
        if (frame.size() < offset + 4) return std::nullopt;
        ethertype = be16(frame, offset + 2);
        offset += 4;
      }
      break;
    case DLT_LINUX_SLL:  // 16 bytes; the protocol (an ethertype) last
      if (frame.size() < 16) return std::nullopt;
      ethertype = be16(frame, 14);
      offset = 16;
      break;
    case DLT_LINUX_SLL2:  // 20 bytes; the protocol first
      if (frame.size() < 20) return std::nullopt;
      ethertype = be16(frame, 0);
      offset = 20;
      break;
    case DLT_NULL:
    case DLT_LOOP: {  // 4 bytes of address family (host order for NULL, network order for LOOP)
      if (frame.size() < 5) return std::nullopt;
      offset = 4;
      // The family's value differs between systems (AF_INET6 is 10, 24, 28 or 30); the IP version
      // nibble of the packet says the same without that table.
      const auto family = frame[0] | frame[1] | frame[2] | frame[3];
      if (family != 2 && family != 10 && family != 24 && family != 28 && family != 30) {
        why = DecodeResult::other;
        return std::nullopt;
      }
      ethertype = (frame[4] >> 4) == 6 ? kEtherIpv6 : kEtherIpv4;
      break;
    }
    case DLT_RAW:
    case DLT_IPV4:
    case DLT_IPV6:
      if (frame.empty()) return std::nullopt;
      ethertype = (frame[0] >> 4) == 6 ? kEtherIpv6 : kEtherIpv4;
      break;
    default: why = DecodeResult::other; return std::nullopt;
  }
  if (ethertype != kEtherIpv4 && ethertype != kEtherIpv6) {
    why = DecodeResult::other;
    return std::nullopt;
  }
  return frame.subspan(offset);
}

}  // namespace

bool is_supported_link_type(int link_type) {
  switch (link_type) {
    case DLT_EN10MB:
    case DLT_LINUX_SLL:
    case DLT_LINUX_SLL2:
    case DLT_RAW:
    case DLT_IPV4:
    case DLT_IPV6:
    case DLT_NULL:
    case DLT_LOOP: return true;
    default: return false;
  }
}

std::string link_type_text(int link_type) {
  const char* name = pcap_datalink_val_to_name(link_type);
  const char* description = pcap_datalink_val_to_description(link_type);
  if (name == nullptr) return fmt::format("{}", link_type);
  return description ? fmt::format("{} {} ({})", link_type, name, description) : fmt::format("{} {}", link_type, name);
}

std::string to_string(const Flow& flow) {
  char source[INET6_ADDRSTRLEN] = "?";
  char destination[INET6_ADDRSTRLEN] = "?";
  const int family = flow.ip_version == 6 ? AF_INET6 : AF_INET;
  inet_ntop(family, flow.source.data(), source, sizeof source);
  inet_ntop(family, flow.destination.data(), destination, sizeof destination);
  const char* transport = flow.transport == Transport::tcp ? "tcp" : "udp";
  if (flow.ip_version == 6)
    return fmt::format("{} [{}]:{}>[{}]:{}", transport, source, flow.source_port, destination, flow.destination_port);
  return fmt::format("{} {}:{}>{}:{}", transport, source, flow.source_port, destination, flow.destination_port);
}

DecodeResult decode_segment(int link_type, std::span<const std::uint8_t> frame, std::uint32_t wire_length,
                            Segment& out) {
  DecodeResult why = DecodeResult::other;
  const auto ip = ip_packet(link_type, frame, why);
  if (!ip) return why;
  const bool cut = frame.size() < wire_length;  // the snapshot length cut this packet
  const auto short_of = [cut] { return cut ? DecodeResult::snapped : DecodeResult::malformed; };
  Bytes packet = *ip;
  if (packet.empty()) return short_of();
  const int version = packet[0] >> 4;
  std::uint8_t protocol = 0;
  std::size_t header = 0;
  out.flow.source = {};
  out.flow.destination = {};
  if (version == 4) {
    if (packet.size() < 20) return short_of();
    header = static_cast<std::size_t>(packet[0] & 0x0Fu) * 4;
    const std::size_t total = be16(packet, 2);
    if (header < 20 || total < header) return DecodeResult::malformed;
    if (packet.size() < total) return short_of();
    packet = packet.first(total);  // Ethernet pads short frames: the padding is no payload
    if ((be16(packet, 6) & 0x3FFF) != 0) return DecodeResult::fragment;  // more fragments or an offset
    protocol = packet[9];
    std::copy_n(packet.begin() + 12, 4, out.flow.source.begin());
    std::copy_n(packet.begin() + 16, 4, out.flow.destination.begin());
  } else if (version == 6) {
    if (packet.size() < 40) return short_of();
    const std::size_t total = 40 + std::size_t{be16(packet, 4)};
    if (packet.size() < total) return short_of();
    packet = packet.first(total);
    protocol = packet[6];
    header = 40;
    std::copy_n(packet.begin() + 8, 16, out.flow.source.begin());
    std::copy_n(packet.begin() + 24, 16, out.flow.destination.begin());
    // Extension headers: hop-by-hop (0), routing (43), destination options (60); a fragment (44) ends.
    while (protocol == 0 || protocol == 43 || protocol == 60 || protocol == 44) {
      if (protocol == 44) return DecodeResult::fragment;
      if (packet.size() < header + 8) return DecodeResult::malformed;
      protocol = packet[header];
      header += (std::size_t{packet[header + 1]} + 1) * 8;
    }
    if (header > packet.size()) return DecodeResult::malformed;
  } else {
    return DecodeResult::malformed;
  }
  out.flow.ip_version = static_cast<std::uint8_t>(version);
  const Bytes transport = packet.subspan(header);
  if (protocol == kProtoUdp) {
    if (transport.size() < 8) return DecodeResult::malformed;
    const std::size_t length = be16(transport, 4);
    if (length < 8 || length > transport.size()) return DecodeResult::malformed;
    out.flow.transport = Transport::udp;
    out.flow.source_port = be16(transport, 0);
    out.flow.destination_port = be16(transport, 2);
    out.payload = transport.subspan(8, length - 8);
    out.sequence = 0;
    out.syn = out.fin = out.rst = false;
    return DecodeResult::segment;
  }
  if (protocol == kProtoTcp) {
    if (transport.size() < 20) return DecodeResult::malformed;
    const std::size_t offset = static_cast<std::size_t>(transport[12] >> 4) * 4;
    if (offset < 20 || offset > transport.size()) return DecodeResult::malformed;
    out.flow.transport = Transport::tcp;
    out.flow.source_port = be16(transport, 0);
    out.flow.destination_port = be16(transport, 2);
    out.sequence = be32(transport, 4);
    const std::uint8_t flags = transport[13];
    out.fin = (flags & 0x01) != 0;
    out.syn = (flags & 0x02) != 0;
    out.rst = (flags & 0x04) != 0;
    out.payload = transport.subspan(offset);
    return DecodeResult::segment;
  }
  return DecodeResult::other;
}

}  // namespace m2mlat::markers
