// The LED's triggers and the loop that switches it: one poll(2) on the stop descriptor and the
// trigger, its timeout the pending flash's end.
#include "m2mlat/capture/led_trigger.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "m2mlat/capture/gpio_source.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::capture {

namespace {

constexpr std::string_view kBlanks = " \t\r\n";

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(kBlanks) - first + 1);
}

void take_word(std::string_view word, const std::string& where, TriggerInput& out) {
  if (const auto action = parse_led_action(word))
    out.actions.push_back(*action);
  else
    out.refused.push_back(fmt::format("{}: unknown LED command '{}' (on, off, flash)", where,
                                      core::printable(std::string(trim(word)))));
}

class StreamTrigger final : public LedTrigger {
 public:
  StreamTrigger(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  int fd() const override { return fd_; }
  std::string describe() const override { return fmt::format("commands on {}, one a line", name_); }

  bool take(TriggerInput& out) override {
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) return true;
      throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", name_, std::strerror(errno)));
    }
    if (n == 0) {  // closed: a last line without its newline still counts
      if (!trim(pending_).empty()) take_word(pending_, fmt::format("{} line {}", name_, ++line_), out);
      pending_.clear();
      return false;
    }
    pending_.append(buffer, static_cast<std::size_t>(n));
    std::size_t start = 0;
    for (std::size_t end; (end = pending_.find('\n', start)) != std::string::npos; start = end + 1)
      take_word(std::string_view(pending_).substr(start, end - start),
                fmt::format("{} line {}", name_, ++line_), out);
    pending_.erase(0, start);
    return true;
  }

 private:
  int fd_;
  std::string name_;
  std::string pending_;  // the start of a line not yet complete
  long line_ = 0;
};

class EdgeTrigger final : public LedTrigger {
 public:
  EdgeTrigger(GpioDevices& devices, const ChannelSpec& channel, const std::string& node)
      : source_(devices, {channel}, GpioSourceOptions{node, "m2mlat-", kMaxEventBufferSize}) {}
  int fd() const override { return source_.fd(); }
  std::string describe() const override {
    const auto lines = source_.describe();
    return fmt::format("a flash at each edge of {}",
                       lines.empty() ? std::string("the input") : lines.front());
  }
  bool take(TriggerInput& out) override {
    result_.clear();
    source_.read(result_, kMaxEventBufferSize);
    for (auto& e : result_.events) {
      out.actions.push_back(LedAction::flash);
      out.edges.push_back(std::move(e));
    }
    for (const auto& gap : result_.gaps)
      out.refused.push_back(fmt::format("{}: {} edges lost ({})", gap.channel, gap.count, gap.kind));
    return true;
  }

 private:
  GpioSource source_;
  ReadResult result_;
};

}  // namespace

std::optional<LedAction> parse_led_action(std::string_view word) {
  word = trim(word);
  if (word.empty() || word == "flash") return LedAction::flash;
  if (word == "on") return LedAction::on;
  if (word == "off") return LedAction::off;
  return std::nullopt;
}

std::unique_ptr<LedTrigger> stream_trigger(int fd, std::string name) {
  return std::make_unique<StreamTrigger>(fd, std::move(name));
}

std::unique_ptr<LedTrigger> edge_trigger(GpioDevices& devices, const ChannelSpec& channel,
                                         const std::string& node) {
  return std::make_unique<EdgeTrigger>(devices, channel, node);
}

DatagramTrigger::DatagramTrigger(const std::string& address) {
  const auto colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("--listen '{}': give HOST:PORT, e.g. 127.0.0.1:9120", core::printable(address)));
  host_ = address.substr(0, colon);
  std::uint16_t port = 0;
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  if (!core::parse_integer(std::string_view(address).substr(colon + 1), port) ||
      ::inet_pton(AF_INET, host_.c_str(), &sa.sin_addr) != 1)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("--listen '{}': give an IPv4 address and a port 0..65535", core::printable(address)));
  sa.sin_port = htons(port);
  socket_.reset(::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!socket_ || ::bind(socket_.get(), reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("--listen {}: {}", core::printable(address), std::strerror(errno)));
  socklen_t len = sizeof sa;
  ::getsockname(socket_.get(), reinterpret_cast<sockaddr*>(&sa), &len);
  port_ = ntohs(sa.sin_port);
}

std::string DatagramTrigger::describe() const {
  return fmt::format("commands as UDP datagrams on {}:{}", host_, port_);
}

bool DatagramTrigger::take(TriggerInput& out) {
  char buffer[512];
  for (;;) {
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t n =
        ::recvfrom(socket_.get(), buffer, sizeof buffer, 0, reinterpret_cast<sockaddr*>(&from), &len);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return true;
      throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", describe(), std::strerror(errno)));
    }
    char host[INET_ADDRSTRLEN] = "?";
    ::inet_ntop(AF_INET, &from.sin_addr, host, sizeof host);
    take_word(std::string_view(buffer, static_cast<std::size_t>(n)),
              fmt::format("datagram from {}:{}", host, ntohs(from.sin_port)), out);
  }
}

LedRunSummary run_triggered(PulseGenerator& led, LedTrigger& trigger, core::Duration on_for, int stop_fd,
                            const std::function<void(const PulseEdge&)>& on_edge,
                            const std::function<void(const TriggerInput&)>& on_input,
                            const std::function<std::string()>& stop_name) {
  if (on_for.count() <= 0) throw core::Error(core::ErrorKind::usage, "--on-for must be positive");
  LedRunSummary summary;
  bool flash_lit = false;
  std::int64_t off_at = 0;  // the lit flash's end, CLOCK_REALTIME ns
  bool open = true;
  const auto switch_to = [&](bool high, core::TimePoint asked) {
    if (led.high() == high) return;
    const auto edge = led.set(high, summary.switches++, asked);
    if (on_edge) on_edge(edge);
  };
  TriggerInput input;
  for (;;) {
    int timeout_ms = -1;
    if (flash_lit) {
      const std::int64_t left = off_at - core::now_ns(CLOCK_REALTIME);
      if (left <= 0) {
        switch_to(false, core::TimePoint::from_ns(core::Clock::realtime, off_at));
        flash_lit = false;
        continue;
      }
      timeout_ms = static_cast<int>(std::min<std::int64_t>((left + 999'999) / 1'000'000, 1000));
    } else if (!open) {
      summary.stop_reason = "end of input";
      break;
    }
    pollfd fds[2] = {{stop_fd, POLLIN, 0}, {open ? trigger.fd() : -1, POLLIN, 0}};
    const int ready = ::poll(fds, 2, timeout_ms);
    if (ready < 0) {
      if (errno == EINTR) continue;
      throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
    }
    if (stop_fd >= 0 && (fds[0].revents & POLLIN) != 0) {
      summary.stop_reason = stop_name ? stop_name() : "stop";
      if (summary.stop_reason.empty()) summary.stop_reason = "stop";
      break;
    }
    if (!open || fds[1].revents == 0) continue;
    const auto asked = core::realtime_now();  // when the trigger was seen: the deadline of what it asks for
    input.actions.clear();
    input.edges.clear();
    input.refused.clear();
    open = trigger.take(input);
    for (const auto action : input.actions) {
      ++summary.triggers;
      switch (action) {
        case LedAction::on:
          flash_lit = false;
          switch_to(true, asked);
          break;
        case LedAction::off:
          flash_lit = false;
          switch_to(false, asked);
          break;
        case LedAction::flash:
          switch_to(true, asked);
          flash_lit = true;
          off_at = asked.ns() + on_for.count();
          break;
      }
    }
    // Only now, with the line switched: recording the trigger's edges (a store's commit) must not delay
    // the LED.
    if (on_input) on_input(input);
  }
  switch_to(false, core::realtime_now());
  return summary;
}

}  // namespace m2mlat::capture
