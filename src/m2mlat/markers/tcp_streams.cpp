#include "m2mlat/markers/tcp_streams.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"

namespace m2mlat::markers {

namespace {
constexpr std::size_t kPrefixBytes = 4;
}  // namespace

void TcpStreams::feed(const Segment& segment, std::string_view capture, std::uint64_t packet_index,
                      const OnMessage& on_message) {
  auto found = streams_.find(segment.flow);
  if (segment.syn) {
    // A new connection on this flow: its data starts after the SYN's sequence number.
    if (found != streams_.end()) {
      ended_incomplete_ += found->second.buffer.size() - found->second.consumed;
      streams_.erase(found);
    }
    Stream stream;
    stream.next_sequence = segment.sequence + 1;
    found = streams_.emplace(segment.flow, std::move(stream)).first;
  } else if (found == streams_.end()) {
    if (segment.payload.empty()) return;  // an ACK of a connection that began before the capture
    Stream stream;
    stream.next_sequence = segment.sequence;  // the capture began mid-stream: start here
    found = streams_.emplace(segment.flow, std::move(stream)).first;
  }
  Stream& stream = found->second;
  if (!segment.payload.empty()) {
    // Sequence numbers wrap at 2^32: the signed distance from the next expected byte places the
    // segment in the stream (segments are never 2 GiB apart).
    const auto distance = static_cast<std::int32_t>(segment.sequence - stream.next_sequence);
    const auto offset = static_cast<std::uint64_t>(static_cast<std::int64_t>(stream.next) + distance);
    const std::uint64_t end = offset + segment.payload.size();
    if (end <= stream.next) {
      ++retransmitted_;
    } else if (offset > stream.next) {
      ++out_of_order_;
      auto& held = stream.ahead[offset];
      if (held.size() < segment.payload.size()) held.assign(segment.payload.begin(), segment.payload.end());
    } else {
      append(stream, offset, segment.payload);
      // Segments that waited for this one: in order of offset, each now adjacent or overlapping.
      while (!stream.ahead.empty() && stream.ahead.begin()->first <= stream.next) {
        auto node = stream.ahead.extract(stream.ahead.begin());
        if (node.key() + node.mapped().size() > stream.next) append(stream, node.key(), node.mapped());
      }
      cut(stream, segment.flow, capture, packet_index, on_message);
    }
  }
  // A FIN that overtook data still missing keeps the stream: the gap may yet be filled.
  if (segment.rst || (segment.fin && stream.ahead.empty())) {
    ended_incomplete_ += stream.buffer.size() - stream.consumed;
    streams_.erase(found);
  }
}


void TcpStreams::append(Stream& stream, std::uint64_t offset, std::span<const std::uint8_t> bytes) {
  const auto skip = static_cast<std::size_t>(stream.next - offset);  // bytes already in the stream
  const auto fresh = bytes.subspan(skip);
  stream.buffer.insert(stream.buffer.end(), fresh.begin(), fresh.end());
  stream.next += fresh.size();
  stream.next_sequence += static_cast<std::uint32_t>(fresh.size());
}

void TcpStreams::cut(Stream& stream, const Flow& flow, std::string_view capture, std::uint64_t packet_index,
                     const OnMessage& on_message) {
  for (;;) {
    const std::size_t available = stream.buffer.size() - stream.consumed;
    if (available < kPrefixBytes) break;
    const std::uint8_t* p = stream.buffer.data() + stream.consumed;
    const std::uint32_t length = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                                 (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
    if (length > max_message_)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: packet {}: {}: a message length of {} bytes (more than {}): the stream is "
                                    "not 4-byte big-endian length-prefixed messages, or the capture began inside one",
                                    capture, packet_index, to_string(flow), length, max_message_));
    if (available < kPrefixBytes + length) break;
    on_message(std::span<const std::uint8_t>(p + kPrefixBytes, length), flow);
    stream.consumed += kPrefixBytes + length;
  }
  // Drop what was given out once it is most of the buffer: amortised O(1) per byte.
  if (stream.consumed > 0 && stream.consumed * 2 >= stream.buffer.size()) {
    stream.buffer.erase(stream.buffer.begin(), stream.buffer.begin() + static_cast<std::ptrdiff_t>(stream.consumed));
    stream.consumed = 0;
  }
}

std::uint64_t TcpStreams::incomplete_bytes() const {
  std::uint64_t bytes = ended_incomplete_;
  for (const auto& [flow, stream] : streams_) {
    bytes += stream.buffer.size() - stream.consumed;
    for (const auto& [offset, held] : stream.ahead) bytes += held.size();  // waiting behind a gap
  }
  return bytes;
}

}  // namespace m2mlat::markers
