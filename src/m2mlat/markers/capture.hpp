// One libpcap handle: a pcap or pcapng file read with nanosecond timestamps, or a live capture on an
// interface (nanosecond timestamps; the adapter's hardware clock where the interface offers it, else
// the kernel's), with an optional BPF filter and an optional copy of every packet to a file.
//
// Packets are read one at a time (next()), so a reader keeps every packet before a damaged one: a
// truncated file throws core::Error(data) naming the file and the packet's index only when that
// packet is reached.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "m2mlat/markers/marker.hpp"

struct pcap;
struct pcap_dumper;

namespace m2mlat::markers {

// One packet as libpcap gives it; the bytes stay valid until the next call of next().
struct RawPacket {
  std::int64_t time_ns = 0;       // CLOCK_REALTIME, ns (the capture's timestamp)
  std::uint64_t index = 0;        // 1-based position in the capture (before the filter: see next())
  std::span<const std::uint8_t> bytes;  // the captured bytes (at most the snapshot length)
  std::uint32_t wire_length = 0;  // the packet's length on the wire, bytes
};

struct LiveOptions {
  std::string interface;
  int snapshot_bytes = 65535;  // bytes kept of each packet
  int buffer_bytes = 4 << 20;  // the kernel's ring for this capture, bytes
  bool prefer_adapter = true;  // the adapter's timestamps where the interface has them
};

class Capture {
 public:
  // Throws core::Error(no_input) when the file is missing, (data) when it is not a capture file or its
  // link type is not one m2mlat decodes (the message names the file and the type).
  static Capture open_file(const std::string& path);
  // Throws core::Error(no_input) for an unknown interface, (io) when capturing is not permitted.
  static Capture open_live(const LiveOptions& options);

  Capture(Capture&&) noexcept;
  Capture& operator=(Capture&&) noexcept;
  ~Capture();

  // Only packets that pass the BPF filter (tcpdump's syntax) are returned from now on. Throws
  // core::Error(usage) quoting the filter and libpcap's complaint.
  void set_filter(const std::string& bpf);
  // Every packet returned from now on is also written to `path` (pcap, nanosecond timestamps).
  void write_to(const std::string& path);

  // The next packet that passes the filter: true with `packet` filled; false at the end of a file,
  // or when a live capture's
  // read timeout (100 ms) passed without one. Throws core::Error(data) for a truncated or damaged
  // file, naming the file and the packet's index.
  bool next(RawPacket& packet);
  bool is_live() const { return live_; }

  int link_type() const { return link_type_; }  // DLT_* (checked: one decode_link() handles)
  StampSource stamp_source() const { return source_; }
  const std::string& name() const { return name_; }  // the file's path or the interface
  // The kernel's drop count of a live capture (packets it had no room for); 0 for a file.
  std::uint64_t dropped() const;
  // Packets read so far, before the filter.
  std::uint64_t read() const { return read_; }

 private:
  Capture(pcap* handle, std::string name, bool live, StampSource source);
  void close();

  pcap* handle_ = nullptr;
  pcap_dumper* dumper_ = nullptr;
  std::string name_;
  bool live_ = false;
  StampSource source_ = StampSource::file;
  int link_type_ = 0;
  std::uint64_t read_ = 0;  // packets read so far (a file's every packet, before the filter)
  struct Filter;
  std::shared_ptr<Filter> filter_;  // a file's compiled filter (a live capture's is in the kernel)
};

}  // namespace m2mlat::markers
