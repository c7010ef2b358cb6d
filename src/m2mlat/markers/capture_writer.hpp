// The captures' twin: frames of every link type m2mlat decodes, built from a flow and a payload, and
// written to a pcap file with nanosecond timestamps through libpcap's own writer (pcap_dump), as
// tcpdump would write them. Tests and the benchmark make their captures with it, so that every
// capture they read has a known truth; no capture file is copied into the tree.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/markers/packet_decode.hpp"

struct pcap;
struct pcap_dumper;

namespace m2mlat::markers {

// A flow from dotted (IPv4) or colon (IPv6) address text; throws core::Error(usage) for bad text.
Flow make_flow(Transport transport, std::string_view source, std::uint16_t source_port, std::string_view destination,
               std::uint16_t destination_port);

inline constexpr std::uint8_t kTcpAck = 0x10;
inline constexpr std::uint8_t kTcpPush = 0x08;
inline constexpr std::uint8_t kTcpSyn = 0x02;
inline constexpr std::uint8_t kTcpFin = 0x01;

// One frame of `link_type` (DLT_*) carrying an IP packet with the flow's UDP datagram or TCP segment
// (sequence number and flags for TCP). Checksums are left zero: m2mlat does not check them.
std::vector<std::uint8_t> build_frame(int link_type, const Flow& flow, std::span<const std::uint8_t> payload,
                                      std::uint32_t sequence = 0, std::uint8_t tcp_flags = kTcpAck | kTcpPush);

// A message with its 4-byte big-endian length before it, as the teleoperation stack sends it on TCP.
std::vector<std::uint8_t> length_prefixed(std::string_view message);
std::span<const std::uint8_t> bytes_of(std::string_view text);

class CaptureWriter {
 public:
  CaptureWriter(const std::string& path, int link_type);  // throws core::Error(io)
  CaptureWriter(const CaptureWriter&) = delete;
  CaptureWriter& operator=(const CaptureWriter&) = delete;
  ~CaptureWriter();
  // wire_length 0: the frame's own size (nothing cut by a snapshot length).
  void write(std::int64_t time_ns, std::span<const std::uint8_t> frame, std::uint32_t wire_length = 0);
  void close();  // flushes and closes (also on destruction)

 private:
  pcap* dead_ = nullptr;
  pcap_dumper* dumper_ = nullptr;
};

}  // namespace m2mlat::markers
