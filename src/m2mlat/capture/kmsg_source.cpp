// /dev/kmsg records and followed files, through formats::parse_kernel_log_line.
#include "m2mlat/capture/kmsg_source.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <optional>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/kernel_log.hpp"

namespace m2mlat::capture {

namespace {

// The sequence number of a /dev/kmsg record, "<priority>,<seq>,<us>,<flags>;message", whatever the
// message: every record counts, GPIO line or not.
std::optional<std::uint64_t> kmsg_record_seq(std::string_view line) {
  const auto semicolon = line.find(';');
  if (semicolon == std::string_view::npos) return std::nullopt;
  const auto header = line.substr(0, semicolon);
  const auto first = header.find(',');
  if (first == std::string_view::npos) return std::nullopt;
  const auto second = header.find(',', first + 1);
  if (second == std::string_view::npos) return std::nullopt;
  for (char c : header.substr(0, first))
    if (c < '0' || c > '9') return std::nullopt;
  std::uint64_t seq = 0;
  const auto text = header.substr(first + 1, second - first - 1);
  if (!core::parse_integer(text, seq)) return std::nullopt;
  return seq;
}

}  // namespace

bool KmsgSource::pin_of(const std::string& line, std::uint32_t& pin) {
  std::size_t digits = 0;
  while (digits < line.size() && std::isalpha(static_cast<unsigned char>(line[digits]))) ++digits;
  return core::parse_integer(std::string_view(line).substr(digits), pin);
}

KmsgSource::KmsgSource(KmsgSourceOptions options) : options_(std::move(options)) {
  for (std::size_t i = 0; i < options_.channels.size(); ++i) {
    std::uint32_t pin = 0;
    if (!pin_of(options_.channels[i].line, pin))
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("channel '{}': line '{}' is not a GPIO pin number (e.g. 16 or GPIO16)",
                                    options_.channels[i].name, options_.channels[i].line));
    if (!by_pin_.emplace(pin, i).second)
      throw core::Error(core::ErrorKind::usage, fmt::format("two channels watch pin {}", pin));
  }
  fd_.reset(::open(options_.path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (!fd_) {
    const int err = errno;
    if (err == ENOENT)
      throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such file", options_.path));
    if (err == EACCES || err == EPERM)
      throw core::Error(
          core::ErrorKind::io,
          fmt::format("{}: permission denied: reading the kernel log needs CAP_SYSLOG (root) or "
                      "`sysctl kernel.dmesg_restrict=0`",
                      options_.path));
    throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", options_.path, std::strerror(err)));
  }
  struct stat st {};
  device_ = ::fstat(fd_.get(), &st) == 0 && S_ISCHR(st.st_mode);
  // The device: only records from now on (older ones belong to earlier runs).
  if (device_) ::lseek(fd_.get(), 0, SEEK_END);
}

KmsgSource::~KmsgSource() = default;

void KmsgSource::take_line(std::string_view line, ReadResult& out) {
  ++lines_;
  const auto parsed = formats::parse_kernel_log_line(line);
  if (const auto seq = kmsg_record_seq(line)) {
    if (const auto gap = kmsg_seq_.observe(*seq))
      out.gaps.push_back({"", "kmsg_gap", gap->first, gap->count});
  }
  if (parsed.kind == formats::KernelLineKind::malformed) {
    if (malformed_++ == 0) first_malformed_ = fmt::format("line {}: {}", lines_, parsed.describe());
    return;
  }
  if (parsed.kind != formats::KernelLineKind::record) return;
  core::Event event;
  event.node = options_.node;
  event.edge = core::Edge::falling;
  if (options_.channels.empty()) {
    event.channel = fmt::format("gpio{}", parsed.record.pin);
  } else {
    const auto it = by_pin_.find(parsed.record.pin);
    if (it == by_pin_.end()) {
      ++other_pins_;
      return;
    }
    const auto& spec = options_.channels[it->second];
    event.channel = spec.name;
    if (spec.edges == Edges::rising) event.edge = core::Edge::rising;
  }
  event.time = core::TimePoint::from_ns(core::Clock::realtime, parsed.record.time_ns);
  event.flags = core::kFlagNoKernelSeqno;
  out.events.push_back(std::move(event));
}

void KmsgSource::read(ReadResult& out, std::size_t max_events) {
  const auto start = out.events.size();
  std::array<char, 8192> buffer{};
  while (out.events.size() - start < max_events) {
    const ssize_t n = ::read(fd_.get(), buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN) break;
      if (errno == EPIPE && device_) continue;  // records overwritten: the next one shows the jump
      throw core::Error(core::ErrorKind::io, fmt::format("{}: {}", options_.path, std::strerror(errno)));
    }
    if (n == 0) break;  // a file's current end: more may be appended later
    const std::string_view chunk(buffer.data(), static_cast<std::size_t>(n));
    if (device_) {  // one record: "prio,seq,us,flags;message\n" then " KEY=value" continuation lines
      take_line(chunk.substr(0, chunk.find('\n')), out);
      continue;
    }
    partial_.append(chunk);
    std::size_t begin = 0;
    if (skipping_) {  // the rest of a line too long to keep
      begin = partial_.find('\n');
      if (begin == std::string::npos) {
        partial_.clear();
        continue;
      }
      ++begin;
      skipping_ = false;
    }
    for (auto nl = partial_.find('\n', begin); nl != std::string::npos; nl = partial_.find('\n', begin)) {
      take_line(std::string_view(partial_).substr(begin, nl - begin), out);
      begin = nl + 1;
    }
    partial_.erase(0, begin);
    if (partial_.size() > formats::kMaxLineBytes) {
      // No GPIO line is this long: pass it over (as malformed) rather than hold it without bound.
      ++lines_;
      if (malformed_++ == 0)
        first_malformed_ = fmt::format("line {}: longer than {} bytes", lines_, formats::kMaxLineBytes);
      partial_.clear();
      skipping_ = true;
    }
  }
}

std::vector<std::string> KmsgSource::describe() const {
  std::vector<std::string> lines;
  const auto kind = device_ ? "kernel log device, new records" : "followed file";
  if (options_.channels.empty())
    lines.push_back(fmt::format("every pin: {} ({}), channel gpio<pin>", options_.path, kind));
  for (const auto& [pin, index] : by_pin_)
    lines.push_back(fmt::format("{}: GPIO_{}_IRQ lines of {} ({})", options_.channels[index].name, pin,
                                options_.path, kind));
  return lines;
}

std::vector<std::string> KmsgSource::channels() const {
  std::vector<std::string> names;
  for (const auto& c : options_.channels) names.push_back(c.name);
  return names;
}

std::vector<std::string> KmsgSource::notes() const {
  std::vector<std::string> out;
  if (malformed_ > 0)
    out.push_back(fmt::format("{}: {} GPIO line(s) were malformed and passed over, the first at {}",
                              options_.path, malformed_, first_malformed_));
  if (other_pins_ > 0)
    out.push_back(fmt::format("{}: {} record(s) of pins no channel watches were passed over", options_.path,
                              other_pins_));
  return out;
}

}  // namespace m2mlat::capture
