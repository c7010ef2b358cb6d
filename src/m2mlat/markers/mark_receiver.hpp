// The software markers' UDP port: receives `m2mlat-mark/1` datagrams (mark_datagram.hpp) and stamps
// each on arrival. The stamp is the kernel's receive time (SO_TIMESTAMPNS, CLOCK_REALTIME: taken
// when the datagram reached the socket, before any wake-up of this program), or, where the kernel
// gives none, clock_gettime(CLOCK_REALTIME) right after the read; the marker's source says which
// (StampSource::kernel / receiver). The kernel switches receive stamping on through deferred work when
// the socket asks for it, so a datagram in the first moments after the port opens may carry the
// time it was read instead; the agent opens the port at start, long before the first real marker.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <sys/socket.h>

#include "m2mlat/core/fd.hpp"
#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

// One datagram read: its marker, or why it was refused (mark_datagram.hpp's reasons).
struct ReceivedMark {
  std::optional<Marker> marker;  // node empty: the receiver does not know it
  std::string_view reason;       // empty when accepted
  std::string detail;            // "<sender address>: <what was wrong>"
  sockaddr_storage from{};       // the sender, for the acknowledgement
  socklen_t from_length = 0;
};

// The acknowledgement a receiver sends back to a mark's sender, one datagram:
// "m2mlat-mark-ack/1 stored <session id>" or "m2mlat-mark-ack/1 refused <reason>: <detail>".
inline constexpr std::string_view kMarkAckPrefix = "m2mlat-mark-ack/1 ";

class MarkReceiver {
 public:
  // Binds a UDP socket to `address` (a numeric IPv4 or IPv6 address; "127.0.0.1" keeps it to this
  // machine) and `port` (0: any free one). Throws core::Error: usage for a bad address, io when the
  // bind is refused (port in use).
  MarkReceiver(const std::string& address, int port);

  int fd() const { return fd_.get(); }  // readable when a datagram waits
  int port() const { return port_; }
  std::string address() const;            // "127.0.0.1:7010", "[::1]:7010"
  bool kernel_stamps() const { return kernel_stamps_; }

  // Reads one waiting datagram without blocking; nullopt when none waits.
  std::optional<ReceivedMark> receive();
  // Sends `text` (after kMarkAckPrefix) back to the sender of `mark`, without blocking; a sender that
  // does not read acknowledgements (any program may send marks) loses nothing.
  void acknowledge(const ReceivedMark& mark, std::string_view text) const;

 private:
  core::Fd fd_;
  std::string host_;
  int port_ = 0;
  bool kernel_stamps_ = false;
};

}  // namespace m2mlat::markers
