#include "m2mlat/markers/capture_writer.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <pcap/pcap.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::markers {

namespace {

void put16(std::vector<std::uint8_t>& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value >> 8));
  out.push_back(static_cast<std::uint8_t>(value));
}
void put32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  put16(out, static_cast<std::uint16_t>(value >> 16));
  put16(out, static_cast<std::uint16_t>(value));
}

std::vector<std::uint8_t> build_ip_packet(const Flow& flow, std::span<const std::uint8_t> payload, std::uint32_t sequence,
                                    std::uint8_t tcp_flags) {
  std::vector<std::uint8_t> transport;
  put16(transport, flow.source_port);
  put16(transport, flow.destination_port);
  std::uint8_t protocol = 17;
  if (flow.transport == Transport::udp) {
    put16(transport, static_cast<std::uint16_t>(8 + payload.size()));
    put16(transport, 0);
  } else {
    protocol = 6;
    put32(transport, sequence);
    put32(transport, 0);     // acknowledgement number
    transport.push_back(5 << 4);  // 20-byte header
    transport.push_back(tcp_flags);
    put16(transport, 65535);  // window
    put32(transport, 0);      // checksum, urgent pointer
  }
  transport.insert(transport.end(), payload.begin(), payload.end());
  std::vector<std::uint8_t> packet;
  if (flow.ip_version == 6) {
    put32(packet, 0x60000000u);
    put16(packet, static_cast<std::uint16_t>(transport.size()));
    packet.push_back(protocol);
    packet.push_back(64);
    packet.insert(packet.end(), flow.source.begin(), flow.source.end());
    packet.insert(packet.end(), flow.destination.begin(), flow.destination.end());
  } else {
    packet.push_back(0x45);
    packet.push_back(0);
    put16(packet, static_cast<std::uint16_t>(20 + transport.size()));
    put32(packet, 0x00004000u);  // identification 0, don't fragment
    packet.push_back(64);
    packet.push_back(protocol);
    put16(packet, 0);
    packet.insert(packet.end(), flow.source.begin(), flow.source.begin() + 4);
    packet.insert(packet.end(), flow.destination.begin(), flow.destination.begin() + 4);
  }
  packet.insert(packet.end(), transport.begin(), transport.end());
  return packet;
}

}  // namespace

Flow make_flow(Transport transport, std::string_view source, std::uint16_t source_port, std::string_view destination,
               std::uint16_t destination_port) {
  Flow flow;
  flow.transport = transport;
  flow.source_port = source_port;
  flow.destination_port = destination_port;
  const bool v6 = source.find(':') != std::string_view::npos;
  flow.ip_version = v6 ? 6 : 4;
  const int family = v6 ? AF_INET6 : AF_INET;
  if (inet_pton(family, std::string(source).c_str(), flow.source.data()) != 1 ||
      inet_pton(family, std::string(destination).c_str(), flow.destination.data()) != 1)
    throw core::Error(core::ErrorKind::usage, fmt::format("address '{}' or '{}': not an IP address", source, destination));
  return flow;
}

std::vector<std::uint8_t> build_frame(int link_type, const Flow& flow, std::span<const std::uint8_t> payload,
                                      std::uint32_t sequence, std::uint8_t tcp_flags) {
  const auto packet = build_ip_packet(flow, payload, sequence, tcp_flags);
  const std::uint16_t ethertype = flow.ip_version == 6 ? 0x86DD : 0x0800;
  std::vector<std::uint8_t> frame;
  switch (link_type) {
    case DLT_EN10MB:
      frame = {0x02, 0, 0, 0, 0, 2, 0x02, 0, 0, 0, 0, 1};  // destination, source MAC
      put16(frame, ethertype);
      break;
    case DLT_LINUX_SLL:
      put16(frame, 0);  // packet type: to us
      put16(frame, 1);  // ARPHRD_ETHER
      put16(frame, 6);  // address length
      frame.insert(frame.end(), {0x02, 0, 0, 0, 0, 1, 0, 0});
      put16(frame, ethertype);
      break;
    case DLT_LINUX_SLL2:
      put16(frame, ethertype);
      put16(frame, 0);  // reserved
      put32(frame, 2);  // interface index
      put16(frame, 1);  // ARPHRD_ETHER
      frame.push_back(0);  // packet type
      frame.push_back(6);  // address length
      frame.insert(frame.end(), {0x02, 0, 0, 0, 0, 1, 0, 0});
      break;
    case DLT_NULL: {  // the family in the writer's byte order (little-endian here)
      const std::uint32_t family = flow.ip_version == 6 ? 10 : 2;
      for (int i = 0; i < 4; ++i) frame.push_back(static_cast<std::uint8_t>(family >> (8 * i)));
      break;
    }
    case DLT_LOOP: put32(frame, flow.ip_version == 6 ? 24 : 2); break;
    case DLT_RAW:
    case DLT_IPV4:
    case DLT_IPV6: break;
    default:
      throw core::Error(core::ErrorKind::usage, fmt::format("link type {}: no frame builder", link_type_text(link_type)));
  }
  frame.insert(frame.end(), packet.begin(), packet.end());
  return frame;
}

std::vector<std::uint8_t> length_prefixed(std::string_view message) {
  std::vector<std::uint8_t> out;
  put32(out, static_cast<std::uint32_t>(message.size()));
  const auto body = bytes_of(message);
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

CaptureWriter::CaptureWriter(const std::string& path, int link_type) {
  dead_ = pcap_open_dead_with_tstamp_precision(link_type, 65535, PCAP_TSTAMP_PRECISION_NANO);
  if (dead_ == nullptr) throw core::Error(core::ErrorKind::internal, "pcap_open_dead failed");
  dumper_ = pcap_dump_open(dead_, path.c_str());
  if (dumper_ == nullptr) {
    const std::string why = pcap_geterr(dead_);
    pcap_close(dead_);
    throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot write: {}", path, why));
  }
}

CaptureWriter::~CaptureWriter() { close(); }

void CaptureWriter::close() {
  if (dumper_ != nullptr) pcap_dump_close(dumper_);
  if (dead_ != nullptr) pcap_close(dead_);
  dumper_ = nullptr;
  dead_ = nullptr;
}

void CaptureWriter::write(std::int64_t time_ns, std::span<const std::uint8_t> frame, std::uint32_t wire_length) {
  pcap_pkthdr header{};
  header.ts.tv_sec = time_ns / 1'000'000'000;
  header.ts.tv_usec = time_ns % 1'000'000'000;  // nanoseconds: the dead handle's precision is nano
  header.caplen = static_cast<std::uint32_t>(frame.size());
  header.len = wire_length != 0 ? wire_length : header.caplen;
  pcap_dump(reinterpret_cast<u_char*>(dumper_), &header, frame.data());
}

}  // namespace m2mlat::markers
