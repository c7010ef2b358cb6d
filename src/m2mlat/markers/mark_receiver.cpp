#include "m2mlat/markers/mark_receiver.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/mark_datagram.hpp"

namespace m2mlat::markers {

namespace {

std::string sender_text(const sockaddr_storage& from) {
  std::array<char, INET6_ADDRSTRLEN> host{};
  if (from.ss_family == AF_INET) {
    const auto& in = reinterpret_cast<const sockaddr_in&>(from);
    ::inet_ntop(AF_INET, &in.sin_addr, host.data(), host.size());
    return fmt::format("{}:{}", host.data(), ntohs(in.sin_port));
  }
  if (from.ss_family == AF_INET6) {
    const auto& in6 = reinterpret_cast<const sockaddr_in6&>(from);
    ::inet_ntop(AF_INET6, &in6.sin6_addr, host.data(), host.size());
    return fmt::format("[{}]:{}", host.data(), ntohs(in6.sin6_port));
  }
  return "?";
}

}  // namespace

MarkReceiver::MarkReceiver(const std::string& address, int port) : host_(address) {
  if (port < 0 || port > 65535)
    throw core::Error(core::ErrorKind::usage, fmt::format("marker port {}: expected 0 to 65535", port));
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_NUMERICHOST | AI_PASSIVE;
  addrinfo* found = nullptr;
  if (::getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || found == nullptr)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("marker address '{}': not a numeric IPv4 or IPv6 address", address));
  const int family = found->ai_family;
  core::Fd fd(::socket(family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!fd) {
    ::freeaddrinfo(found);
    throw core::Error(core::ErrorKind::io, fmt::format("marker port: socket: {}", std::strerror(errno)));
  }
  const int bound = ::bind(fd.get(), found->ai_addr, found->ai_addrlen);
  const int bind_errno = errno;
  ::freeaddrinfo(found);
  if (bound != 0)
    throw core::Error(core::ErrorKind::io, fmt::format("marker port {}:{}: bind: {}", address, port,
                                                       std::strerror(bind_errno)));
  const int on = 1;
  kernel_stamps_ = ::setsockopt(fd.get(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) == 0;
  sockaddr_storage local{};
  socklen_t length = sizeof local;
  if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&local), &length) != 0)
    throw core::Error(core::ErrorKind::io, fmt::format("marker port: getsockname: {}", std::strerror(errno)));
  port_ = family == AF_INET ? ntohs(reinterpret_cast<const sockaddr_in&>(local).sin_port)
                            : ntohs(reinterpret_cast<const sockaddr_in6&>(local).sin6_port);
  fd_ = std::move(fd);
}

std::string MarkReceiver::address() const {
  return host_.find(':') != std::string::npos ? fmt::format("[{}]:{}", host_, port_)
                                               : fmt::format("{}:{}", host_, port_);
}

std::optional<ReceivedMark> MarkReceiver::receive() {
  // One byte more than the largest datagram accepted, so a longer one shows as too long (MSG_TRUNC
  // also says so) instead of being cut to a valid-looking prefix.
  std::array<char, kMarkMaxBytes + 1> buffer{};
  alignas(cmsghdr) std::array<char, CMSG_SPACE(sizeof(timespec))> control{};
  sockaddr_storage from{};
  iovec io{buffer.data(), buffer.size()};
  msghdr message{};
  message.msg_name = &from;
  message.msg_namelen = sizeof from;
  message.msg_iov = &io;
  message.msg_iovlen = 1;
  message.msg_control = control.data();
  message.msg_controllen = control.size();
  ssize_t got = 0;
  do {
    got = ::recvmsg(fd_.get(), &message, MSG_TRUNC);
  } while (got < 0 && errno == EINTR);
  if (got < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::nullopt;
    throw core::Error(core::ErrorKind::io, fmt::format("marker port {}: recvmsg: {}", address(), std::strerror(errno)));
  }
  // The fallback stamp is read at once, before any parsing.
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  std::optional<timespec> kernel;
  for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS && c->cmsg_len >= CMSG_LEN(sizeof(timespec))) {
      timespec ts{};
      std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
      kernel = ts;
    }
  }
  ReceivedMark out;
  out.from = from;
  out.from_length = message.msg_namelen;
  const std::string sender = sender_text(from);
  const auto size = static_cast<std::size_t>(got);
  MarkParse parsed;
  if (size > kMarkMaxBytes || (message.msg_flags & MSG_TRUNC) != 0) {
    parsed.reason = "size";
    parsed.detail = fmt::format("{} bytes or more (at most {})", size, kMarkMaxBytes);
  } else {
    parsed = parse_mark(std::string_view(buffer.data(), size));
  }
  if (!parsed.mark) {
    out.reason = parsed.reason;
    out.detail = fmt::format("{}: {}", sender, parsed.detail);
    return out;
  }
  const timespec stamp = kernel ? *kernel : now;
  Marker m;
  m.name = parsed.mark->name;
  m.time = core::TimePoint::from_ns(core::Clock::realtime,
                                    static_cast<std::int64_t>(stamp.tv_sec) * 1'000'000'000 + stamp.tv_nsec);
  m.source = kernel ? StampSource::kernel : StampSource::receiver;
  m.key = parsed.mark->key;
  if (parsed.mark->sender_ns) m.sender_time = core::TimePoint::from_ns(core::Clock::realtime, *parsed.mark->sender_ns);
  m.origin = fmt::format("udp {}", sender);
  out.marker = std::move(m);
  return out;
}

void MarkReceiver::acknowledge(const ReceivedMark& mark, std::string_view text) const {
  if (mark.from_length == 0) return;
  const std::string datagram = std::string(kMarkAckPrefix) + std::string(text);
  ::sendto(fd_.get(), datagram.data(), datagram.size(), MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&mark.from),
           mark.from_length);
}

}  // namespace m2mlat::markers
