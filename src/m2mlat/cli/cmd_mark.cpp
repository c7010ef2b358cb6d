// `m2mlat mark NAME`: sends one software marker (an m2mlat-mark/1 datagram, docs/markers.md) to an
// agent's marker port, for shell scripts: `m2mlat mark planner_out --key "$seq" --stamp`. The agent
// stamps it on arrival; --stamp also carries this program's own CLOCK_REALTIME, read just before the
// send. It then waits (--wait) for the agent's acknowledgement and says what became of the mark:
// exit 0 stored, 65 refused (the reason), 74 no agent answered (nothing listens there, or no answer
// in time). --wait 0 sends and exits 0 at once (the mark's stamp is taken on arrival either way).
#include <fmt/format.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/host_port.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/markers/mark_receiver.hpp"
#include "m2mlat/markers/mark_datagram.hpp"

namespace m2mlat::cli {

namespace {

struct MarkCommand {
  std::string name;
  std::string key;
  bool stamp = false;
  std::string to = "127.0.0.1:8471";
  std::string wait = "1s";
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
  const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(core::parse_duration(c.wait, 1'000'000));
  core::Fd fd(::socket(found->ai_family, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!fd) throw core::Error(core::ErrorKind::io, fmt::format("socket: {}", std::strerror(errno)));
  // Connected: the agent's answer is the only datagram read, and "port unreachable" shows as an error.
  if (::connect(fd.get(), found->ai_addr, found->ai_addrlen) != 0)
    throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", c.to, std::strerror(errno)));
  if (c.stamp) {
    timespec now{};
    ::clock_gettime(CLOCK_REALTIME, &now);
    mark.sender_ns = static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
  }
  const std::string text = format_mark(mark);
  if (::send(fd.get(), text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
    throw core::Error(core::ErrorKind::io, fmt::format("sending the mark to {}: {}", c.to, std::strerror(errno)));
  if (wait.count() == 0) return 0;
  pollfd ready{fd.get(), POLLIN, 0};
  const int n = ::poll(&ready, 1, static_cast<int>(wait.count()));
  std::array<char, 512> answer{};
  const ssize_t got = n > 0 ? ::recv(fd.get(), answer.data(), answer.size(), 0) : -1;
  if (got < 0) {
    const bool refused = n > 0 && errno == ECONNREFUSED;
    throw core::Error(core::ErrorKind::io,
                      refused ? fmt::format("{}: nothing listens there (is `m2mlat agent --mark-port` running?): the "
                                            "mark is lost",
                                            c.to)
                              : fmt::format("{}: no acknowledgement within {}: the mark may be lost (is `m2mlat agent "
                                            "--mark-port` running there?)",
                                            c.to, c.wait));
  }
  const std::string_view reply(answer.data(), static_cast<std::size_t>(got));
  if (!reply.starts_with(markers::kMarkAckPrefix))
    throw core::Error(core::ErrorKind::io, fmt::format("{}: an answer that is no acknowledgement", c.to));
  const auto what = reply.substr(markers::kMarkAckPrefix.size());
  if (what.starts_with("stored ")) {
    fmt::print("{}: stored by the agent at {} (session {})\n", c.name, c.to, core::printable(what.substr(7)));
    return 0;
  }
  throw core::Error(core::ErrorKind::data, fmt::format("{}: the agent refused the mark: {}", c.to,
                                                       core::printable(what.substr(what.find(' ') + 1))));
}

}  // namespace

Runner attach_mark(CLI::App& sub) {
  auto c = std::make_shared<MarkCommand>();
  sub.add_option("name", c->name, "The point in the pipeline (letters, digits, _ . : / -; at most 64)")->required();
  sub.add_option("--key", c->key, "The command's key, the same on every board (printable, no spaces)");
  sub.add_flag("--stamp", c->stamp, "Carry this program's own CLOCK_REALTIME (ns) in the mark");
  sub.add_option("--to", c->to, "The agent's marker port, HOST:PORT (m2mlat agent --mark-port)")
      ->capture_default_str();
  sub.add_option("--wait", c->wait, "How long to wait for the agent's acknowledgement (0: send and exit)")
      ->capture_default_str();
  return [c] { return run_mark(*c); };
}

}  // namespace m2mlat::cli
