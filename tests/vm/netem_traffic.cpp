// m2mlat-vm-traffic: the two ends of the real-kernel suite's netem test (tests/vm/guest/tests.sh,
// packets.netem), the guest's equivalent of the Python programs in tests/integration/packets_netem.sh
// (the guest has no Python). Static, so the initramfs needs no libraries for it.
//
//   m2mlat-vm-traffic recv ADDR TCP_PORT UDP_PORT
//     Listens on ADDR:TCP_PORT (one connection of length-prefixed JSON commands: a 4-byte big-endian
//     length, then the body) and on ADDR:UDP_PORT (one command per datagram; "end" or 4 s of silence
//     ends it). Prints "ready" on stderr once both sockets are bound, and at the end one "id ns" line
//     per command on stdout: ns is the receiver's CLOCK_REALTIME when the kernel received the
//     segment or datagram that completed the command (SO_TIMESTAMPNS).
//   m2mlat-vm-traffic send ADDR TCP_PORT UDP_PORT N
//     Sends N commands on each transport at 100 Hz (paced on CLOCK_MONOTONIC), each a JSON body
//     {"id": "tK"|"uK", "stamp": <CLOCK_REALTIME in ms, taken before the send>, "steer": ...}, and
//     prints one "id snd sched" line per command: the sender's CLOCK_REALTIME when the driver took the
//     packet (snd) and when it entered the device's queueing (sched), the kernel's software transmit
//     stamps (SO_TIMESTAMPING, read from the socket's error queue). A capture on the sending
//     interface stamps the packet between the two.
#include <arpa/inet.h>
#include <linux/errqueue.h>
#include <linux/net_tstamp.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

[[noreturn]] void die(const char* what) {
  std::fprintf(stderr, "m2mlat-vm-traffic: %s: %s\n", what, std::strerror(errno));
  std::exit(1);
}

std::int64_t ns_of(const timespec& t) { return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec; }

std::int64_t now_ns(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return ns_of(t);
}

sockaddr_in address(const char* ip, int port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  if (inet_pton(AF_INET, ip, &a.sin_addr) != 1) die("bad address");
  return a;
}

sockaddr* as_sockaddr(sockaddr_in& a) { return reinterpret_cast<sockaddr*>(&a); }

void set_int(int fd, int level, int name, int value) {
  if (setsockopt(fd, level, name, &value, sizeof value) != 0) die("setsockopt");
}

// The first timestamp (struct timespec) of the control messages of level SOL_SOCKET and type KIND.
std::int64_t stamp_of(msghdr& m, int kind) {
  for (cmsghdr* c = CMSG_FIRSTHDR(&m); c != nullptr; c = CMSG_NXTHDR(&m, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == kind) {
      timespec t{};
      std::memcpy(&t, CMSG_DATA(c), sizeof t);
      return ns_of(t);
    }
  }
  std::fprintf(stderr, "m2mlat-vm-traffic: no timestamp of type %d\n", kind);
  std::exit(1);
}

// The value of "id" in a JSON body (the bodies are this program's own, so a plain search will do).
std::string id_of(const std::string& body) {
  const auto key = body.find("\"id\"");
  const auto open = body.find('"', body.find(':', key) + 1);
  const auto close = body.find('"', open + 1);
  if (key == std::string::npos || open == std::string::npos || close == std::string::npos) {
    std::fprintf(stderr, "m2mlat-vm-traffic: no id in '%s'\n", body.c_str());
    std::exit(1);
  }
  return body.substr(open + 1, close - open - 1);
}

// recvmsg with room for the control messages; returns the byte count (0 at end of stream).
ssize_t receive(int fd, char* buf, std::size_t size, std::int64_t& stamp) {
  alignas(cmsghdr) char control[256];
  iovec io{buf, size};
  msghdr m{};
  m.msg_iov = &io;
  m.msg_iovlen = 1;
  m.msg_control = control;
  m.msg_controllen = sizeof control;
  const ssize_t n = recvmsg(fd, &m, 0);
  if (n > 0) stamp = stamp_of(m, SCM_TIMESTAMPNS);
  return n;
}

int run_recv(const char* ip, int tcp_port, int udp_port) {
  std::vector<std::pair<std::string, std::int64_t>> out;
  std::mutex lock;
  const auto note = [&](const std::string& body, std::int64_t t) {
    const std::lock_guard<std::mutex> guard(lock);
    out.emplace_back(id_of(body), t);
  };
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  set_int(listener, SOL_SOCKET, SO_REUSEADDR, 1);
  sockaddr_in a = address(ip, tcp_port);
  if (bind(listener, as_sockaddr(a), sizeof a) != 0 || listen(listener, 1) != 0) die("tcp bind");
  const int udp = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in u = address(ip, udp_port);
  if (bind(udp, as_sockaddr(u), sizeof u) != 0) die("udp bind");
  set_int(udp, SOL_SOCKET, SO_TIMESTAMPNS, 1);
  const timeval four_s{4, 0};
  if (setsockopt(udp, SOL_SOCKET, SO_RCVTIMEO, &four_s, sizeof four_s) != 0) die("SO_RCVTIMEO");
  std::fprintf(stderr, "ready\n");

  std::thread tcp_side([&] {
    const int conn = accept(listener, nullptr, nullptr);
    if (conn < 0) die("accept");
    set_int(conn, SOL_SOCKET, SO_TIMESTAMPNS, 1);
    std::string buf;
    char chunk[65536];
    std::int64_t t = 0;
    for (;;) {
      const ssize_t n = receive(conn, chunk, sizeof chunk, t);
      if (n < 0) die("tcp recvmsg");
      if (n == 0) break;
      buf.append(chunk, static_cast<std::size_t>(n));
      while (buf.size() >= 4) {
        const auto* p = reinterpret_cast<const unsigned char*>(buf.data());
        const std::size_t len =
            (std::size_t{p[0]} << 24) | (std::size_t{p[1]} << 16) | (std::size_t{p[2]} << 8) | p[3];
        if (buf.size() < 4 + len) break;
        note(buf.substr(4, len), t);
        buf.erase(0, 4 + len);
      }
    }
    close(conn);
  });
  std::thread udp_side([&] {
    char data[65536];
    std::int64_t t = 0;
    for (;;) {
      const ssize_t n = receive(udp, data, sizeof data, t);
      if (n < 0) break;  // 4 s of silence
      const std::string body(data, static_cast<std::size_t>(n));
      if (body == "end") break;
      note(body, t);
    }
  });
  tcp_side.join();
  udp_side.join();
  for (const auto& [id, t] : out) std::printf("%s %lld\n", id.c_str(), static_cast<long long>(t));
  return 0;
}

// The two software transmit stamps of the last send on FD, from its error queue (which makes it
// readable): "sched" when the packet entered the device's queueing (before the capture tap) and
// "snd" when the driver took it (after the tap). Each arrives as its own message, its kind in the
// extended error's ee_info.
struct SentAt {
  std::int64_t sched = 0;
  std::int64_t snd = 0;
};
SentAt sent_at(int fd) {
  SentAt at;
  for (int attempt = 0; attempt < 8 && (at.sched == 0 || at.snd == 0); ++attempt) {
    pollfd p{fd, POLLIN, 0};
    poll(&p, 1, 250);
    alignas(cmsghdr) char control[512];
    char byte = 0;
    iovec io{&byte, 1};
    msghdr m{};
    m.msg_iov = &io;
    m.msg_iovlen = 1;
    m.msg_control = control;
    m.msg_controllen = sizeof control;
    if (recvmsg(fd, &m, MSG_ERRQUEUE | MSG_DONTWAIT) < 0) continue;
    std::uint32_t kind = ~0U;
    for (cmsghdr* c = CMSG_FIRSTHDR(&m); c != nullptr; c = CMSG_NXTHDR(&m, c)) {
      if (c->cmsg_level == SOL_IP && c->cmsg_type == IP_RECVERR) {
        sock_extended_err e{};
        std::memcpy(&e, CMSG_DATA(c), sizeof e);
        if (e.ee_origin == SO_EE_ORIGIN_TIMESTAMPING) kind = e.ee_info;
      }
    }
    const std::int64_t t = stamp_of(m, SCM_TIMESTAMPING);
    if (kind == SCM_TSTAMP_SCHED) at.sched = t;
    if (kind == SCM_TSTAMP_SND) at.snd = t;
  }
  if (at.sched == 0 || at.snd == 0) {
    std::fprintf(stderr, "m2mlat-vm-traffic: no transmit timestamps\n");
    std::exit(1);
  }
  return at;
}

int run_send(const char* ip, int tcp_port, int udp_port, int count) {
  const int tcp = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a = address(ip, tcp_port);
  if (connect(tcp, as_sockaddr(a), sizeof a) != 0) die("connect");
  set_int(tcp, IPPROTO_TCP, TCP_NODELAY, 1);
  const int udp = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in u = address(ip, udp_port);
  // Software transmit stamps, reported; one per send (OPT_ID), without the packet (OPT_TSONLY).
  const int flags = SOF_TIMESTAMPING_TX_SCHED | SOF_TIMESTAMPING_TX_SOFTWARE | SOF_TIMESTAMPING_SOFTWARE |
                    SOF_TIMESTAMPING_OPT_ID | SOF_TIMESTAMPING_OPT_TSONLY;
  set_int(tcp, SOL_SOCKET, SO_TIMESTAMPING, flags);
  set_int(udp, SOL_SOCKET, SO_TIMESTAMPING, flags);
  const std::int64_t start = now_ns(CLOCK_MONOTONIC);
  constexpr std::int64_t period_ns = 10'000'000;  // 100 Hz
  for (int k = 0; k < count; ++k) {
    const std::int64_t due = start + k * period_ns;
    const timespec wake{static_cast<time_t>(due / 1'000'000'000), static_cast<long>(due % 1'000'000'000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &wake, nullptr) == EINTR) {
    }
    for (const char proto : {'t', 'u'}) {
      const std::string id = proto + std::to_string(k);
      const std::string body = "{\"id\": \"" + id +
                               "\", \"stamp\": " + std::to_string(now_ns(CLOCK_REALTIME) / 1'000'000) +
                               ", \"steer\": " + std::to_string(0.01 * k) + "}";
      if (proto == 't') {
        const auto len = static_cast<std::uint32_t>(body.size());
        const std::string frame = std::string{static_cast<char>(len >> 24), static_cast<char>(len >> 16),
                                              static_cast<char>(len >> 8), static_cast<char>(len)} +
                                  body;
        if (send(tcp, frame.data(), frame.size(), 0) != static_cast<ssize_t>(frame.size())) die("tcp send");
      } else if (sendto(udp, body.data(), body.size(), 0, as_sockaddr(u), sizeof u) < 0) {
        die("udp send");
      }
      const SentAt at = sent_at(proto == 't' ? tcp : udp);
      std::printf("%s %lld %lld\n", id.c_str(), static_cast<long long>(at.snd),
                  static_cast<long long>(at.sched));
    }
  }
  const timespec tenth{0, 100'000'000};
  nanosleep(&tenth, nullptr);
  close(tcp);
  sendto(udp, "end", 3, 0, as_sockaddr(u), sizeof u);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "recv" && argc == 5) return run_recv(argv[2], std::atoi(argv[3]), std::atoi(argv[4]));
  if (mode == "send" && argc == 6)
    return run_send(argv[2], std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5]));
  std::fprintf(stderr,
               "usage: m2mlat-vm-traffic recv ADDR TCP_PORT UDP_PORT\n"
               "       m2mlat-vm-traffic send ADDR TCP_PORT UDP_PORT N\n");
  return 64;
}
