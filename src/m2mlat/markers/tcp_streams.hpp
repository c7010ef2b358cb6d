// TCP streams put back in order and cut into length-prefixed messages (a 4-byte big-endian length,
// then that many bytes: the teleoperation stack's JSON commands), so that however the sender's
// segments split or joined messages, each message comes out once.
//
// Each direction of each connection is one stream. A segment's bytes are placed by their sequence
// number: bytes already seen (a retransmission, an overlap) are dropped, a segment ahead of a gap
// waits until the gap is filled. A message is stamped with the capture time of the packet that
// completed it (the one that brought its last missing byte): the moment the receiver could have read
// it. A stream starts at its SYN, or at the first data segment seen when the capture began later
// (then that segment must start a message). FIN or RST ends it. A segment the capture never saw (the
// kernel dropped it) is a gap that is never filled: the stream's later bytes wait behind it and are
// counted in incomplete_bytes(), never given out as messages.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/markers/packet_decode.hpp"

namespace m2mlat::markers {

class TcpStreams {
 public:
  // A message: its bytes (without the length prefix; valid during the call) and the flow it came on.
  using OnMessage = std::function<void(std::span<const std::uint8_t> message, const Flow& flow)>;

  // max_message_bytes: a length prefix above it means the stream is not length-prefixed messages.
  explicit TcpStreams(std::uint32_t max_message_bytes = 16u << 20) : max_message_(max_message_bytes) {}

  // One TCP segment, packet `packet_index` of the capture `capture`; calls on_message for each message
  // this segment completes. Throws core::Error(data) naming the capture, the packet and the flow when
  // a stream's length prefix exceeds the maximum.
  void feed(const Segment& segment, std::string_view capture, std::uint64_t packet_index, const OnMessage& on_message);

  // Bytes of messages left incomplete (a stream ended, or is still open, inside one, or they wait
  // behind a gap); segments that
  // held only bytes already seen (retransmissions); segments that came after a gap.
  std::uint64_t incomplete_bytes() const;
  std::uint64_t retransmitted_segments() const { return retransmitted_; }
  std::uint64_t out_of_order_segments() const { return out_of_order_; }

 private:
  struct Stream {
    std::uint64_t next = 0;         // the stream offset of the next byte expected
    std::uint32_t next_sequence = 0;  // its sequence number
    std::vector<std::uint8_t> buffer;  // bytes in order not yet cut into messages
    std::size_t consumed = 0;          // bytes of buffer already given out as messages
    std::map<std::uint64_t, std::vector<std::uint8_t>> ahead;  // segments after a gap, by stream offset
  };
  void append(Stream& stream, std::uint64_t offset, std::span<const std::uint8_t> bytes);
  void cut(Stream& stream, const Flow& flow, std::string_view capture, std::uint64_t packet_index,
           const OnMessage& on_message);

  std::map<Flow, Stream> streams_;
  std::uint32_t max_message_;
  std::uint64_t ended_incomplete_ = 0;
  std::uint64_t retransmitted_ = 0;
  std::uint64_t out_of_order_ = 0;
};

}  // namespace m2mlat::markers
