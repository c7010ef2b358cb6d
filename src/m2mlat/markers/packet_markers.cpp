#include "m2mlat/markers/packet_markers.hpp"

#include <fmt/format.h>

#include <map>

#include "m2mlat/markers/packet_decode.hpp"
#include "m2mlat/markers/tcp_streams.hpp"

namespace m2mlat::markers {

CaptureCounts read_markers(Capture& capture, const MarkerOptions& options,
                           const std::function<void(Marker&&)>& on_marker, const std::function<bool()>& keep_going) {
  CaptureCounts counts;
  TcpStreams streams;
  const std::string node = options.node.empty() ? capture.name() : options.node;
  const core::Clock clock = core::Clock::realtime;
  RawPacket packet;
  Segment segment;
  // A flow's text for the markers' origin, made once per flow (a capture has few).
  std::map<Flow, std::string> flow_texts;
  const auto flow_text = [&](const Flow& flow) -> const std::string& {
    auto found = flow_texts.find(flow);
    if (found == flow_texts.end()) found = flow_texts.emplace(flow, " " + to_string(flow)).first;
    return found->second;
  };
  const auto emit = [&](std::span<const std::uint8_t> message, const Flow& flow) {
    ++counts.messages;
    auto found = message_key(options.rule, message);
    if (!found.key) {
      ++counts.without_key;
      return;
    }
    Marker marker;
    marker.node = node;
    marker.name = options.name;
    marker.time = core::TimePoint::from_ns(clock, packet.time_ns);
    marker.source = capture.stamp_source();
    marker.key = std::move(*found.key);
    if (found.sender_ns) marker.sender_time = core::TimePoint::from_ns(clock, *found.sender_ns);
    marker.origin = capture.name();
    marker.origin += '#';
    marker.origin += std::to_string(packet.index);
    marker.origin += flow_text(flow);
    on_marker(std::move(marker));
  };
  while (!keep_going || keep_going()) {
    if (!capture.next(packet)) {
      if (capture.is_live()) continue;  // a read timeout: ask keep_going again
      break;
    }
    ++counts.packets;
    switch (decode_segment(capture.link_type(), packet.bytes, packet.wire_length, segment)) {
      case DecodeResult::segment: break;
      case DecodeResult::other: ++counts.other; continue;
      case DecodeResult::fragment: ++counts.fragments; continue;
      case DecodeResult::snapped: ++counts.snapped; continue;
      case DecodeResult::malformed: ++counts.malformed; continue;
    }
    ++counts.segments;
    if (segment.flow.transport == Transport::udp) {
      emit(segment.payload, segment.flow);
    } else {
      streams.feed(segment, capture.name(), packet.index, emit);
    }
  }
  counts.retransmitted = streams.retransmitted_segments();
  counts.out_of_order = streams.out_of_order_segments();
  counts.incomplete_bytes = streams.incomplete_bytes();
  counts.dropped = capture.dropped();
  counts.seen = capture.read();
  return counts;
}

std::vector<Marker> read_file_markers(const std::string& path, const MarkerOptions& options, CaptureCounts* counts) {
  auto capture = Capture::open_file(path);
  if (!options.rule.filter.empty()) capture.set_filter(options.rule.filter);
  std::vector<Marker> markers;
  const auto c = read_markers(capture, options, [&](Marker&& m) { markers.push_back(std::move(m)); });
  if (counts != nullptr) *counts = c;
  return markers;
}

}  // namespace m2mlat::markers
