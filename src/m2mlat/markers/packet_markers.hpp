// A capture's commands as markers: each packet the rule's filter passes is decoded (packet_decode),
// a UDP payload is one message, a TCP stream is reassembled and cut into length-prefixed messages
// (tcp_streams), and each message with a key (command_rule) becomes one marker stamped with the
// capture time of the packet that completed it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "m2mlat/markers/capture.hpp"
#include "m2mlat/markers/command_rule.hpp"
#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

// What a capture held besides its markers: every count is shown, nothing is dropped silently.
struct CaptureCounts {
  std::uint64_t seen = 0;         // packets read, before the filter
  std::uint64_t packets = 0;      // packets the filter passed
  std::uint64_t segments = 0;     // of them, UDP or TCP segments
  std::uint64_t other = 0;        // of another protocol
  std::uint64_t fragments = 0;    // IP fragments (not reassembled)
  std::uint64_t snapped = 0;      // cut by the snapshot length
  std::uint64_t malformed = 0;    // headers that contradict themselves
  std::uint64_t messages = 0;     // UDP payloads and TCP messages
  std::uint64_t without_key = 0;  // messages the rule found no key in
  std::uint64_t retransmitted = 0;   // TCP segments of bytes already seen
  std::uint64_t out_of_order = 0;    // TCP segments after a gap
  std::uint64_t incomplete_bytes = 0;  // TCP bytes of messages never completed
  std::uint64_t dropped = 0;      // live: packets the kernel had no room for
};

struct MarkerOptions {
  CommandRule rule;
  std::string node;              // the markers' node; empty: the capture's name
  std::string name = "packet";  // the markers' name
};

// Reads `capture` to its end (a file) or until `keep_going` returns false (checked between packets
// and at each read timeout of a live capture); each marker goes to `on_marker` as it is found.
// Throws core::Error(data) on a damaged file: the markers given out before stay given out.
CaptureCounts read_markers(Capture& capture, const MarkerOptions& options,
                           const std::function<void(Marker&&)>& on_marker,
                           const std::function<bool()>& keep_going = {});

// A capture file's markers, all at once.
std::vector<Marker> read_file_markers(const std::string& path, const MarkerOptions& options,
                                      CaptureCounts* counts = nullptr);

}  // namespace m2mlat::markers
