// `m2mlat mark NAME`: sends one software marker (an m2mlat-mark/1 datagram, docs/markers.md) to an
// agent's marker port, for shell scripts: `m2mlat mark planner_out --key "$seq" --stamp`. The agent
// stamps it on arrival; --stamp also carries this program's own CLOCK_REALTIME, read just before the
// send. Exit 0 once the datagram is sent (UDP: the agent does not answer; its status counts what it
// stored and refused).
#include <fmt/format.h>
#include <netdb.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <string>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/host_port.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/markers/mark_datagram.hpp"

namespace m2mlat::cli {

namespace {

struct MarkCommand {
  std::string name;
  std::string key;
  bool stamp = false;
  std::string to = "127.0.0.1:8471";
};

int run_mark(const MarkCommand& c) {
  markers::MarkDatagram mark;
  mark.name = c.name;
  mark.key = c.key;
  format_mark(mark);  // a bad name or key is a usage error before anything is sent
  const auto [host, port] = split_host_port("--to", c.to, "127.0.0.1:8471 or [::1]:8471", false);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (const int rc = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found); rc != 0 || found == nullptr)
    throw core::Error(core::ErrorKind::usage, fmt::format("--to '{}': {}", c.to, ::gai_strerror(rc)));
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> owned(found, &::freeaddrinfo);
  core::Fd fd(::socket(found->ai_family, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!fd) throw core::Error(core::ErrorKind::io, fmt::format("socket: {}", std::strerror(errno)));
  if (c.stamp) {
    timespec now{};
    ::clock_gettime(CLOCK_REALTIME, &now);
    mark.sender_ns = static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
  }
  const std::string text = format_mark(mark);
  if (::sendto(fd.get(), text.data(), text.size(), 0, found->ai_addr, found->ai_addrlen) !=
      static_cast<ssize_t>(text.size()))
    throw core::Error(core::ErrorKind::io, fmt::format("sending the mark to {}: {}", c.to, std::strerror(errno)));
  return 0;
}

}  // namespace

Runner attach_mark(CLI::App& sub) {
  auto c = std::make_shared<MarkCommand>();
  sub.add_option("name", c->name, "The point in the pipeline (letters, digits, _ . : / -; at most 64)")->required();
  sub.add_option("--key", c->key, "The command's key, the same on every board (printable, no spaces)");
  sub.add_flag("--stamp", c->stamp, "Carry this program's own CLOCK_REALTIME (ns) in the mark");
  sub.add_option("--to", c->to, "The agent's marker port, HOST:PORT (m2mlat agent --mark-port)")
      ->capture_default_str();
  return [c] { return run_mark(*c); };
}

}  // namespace m2mlat::cli
