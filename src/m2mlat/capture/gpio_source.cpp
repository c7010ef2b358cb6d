// Requests, epoll, batch reads and decoding of gpio_v2_line_event into core::Event.
#include "m2mlat/capture/gpio_source.hpp"

#include <fmt/format.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "m2mlat/capture/chip_lookup.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

gpio_v2_line_request make_input_request(const ChannelSpec& spec, std::uint32_t offset,
                                        const std::string& consumer, std::uint32_t event_buffer_size) {
  gpio_v2_line_request request{};
  request.offsets[0] = offset;
  request.num_lines = 1;
  const auto label = consumer.substr(0, sizeof request.consumer - 1);
  std::memcpy(request.consumer, label.data(), label.size());
  std::uint64_t flags = GPIO_V2_LINE_FLAG_INPUT;
  if (spec.edges != Edges::rising) flags |= GPIO_V2_LINE_FLAG_EDGE_FALLING;
  if (spec.edges != Edges::falling) flags |= GPIO_V2_LINE_FLAG_EDGE_RISING;
  switch (spec.bias) {
    case Bias::as_is: break;
    case Bias::pull_up: flags |= GPIO_V2_LINE_FLAG_BIAS_PULL_UP; break;
    case Bias::pull_down: flags |= GPIO_V2_LINE_FLAG_BIAS_PULL_DOWN; break;
    case Bias::disabled: flags |= GPIO_V2_LINE_FLAG_BIAS_DISABLED; break;
  }
  if (spec.active_low) flags |= GPIO_V2_LINE_FLAG_ACTIVE_LOW;
  if (spec.clock == EventClock::realtime) flags |= GPIO_V2_LINE_FLAG_EVENT_CLOCK_REALTIME;
  if (spec.clock == EventClock::hte) flags |= GPIO_V2_LINE_FLAG_EVENT_CLOCK_HTE;
  request.config.flags = flags;
  if (spec.debounce.count() > 0) {
    auto& attr = request.config.attrs[request.config.num_attrs++];
    attr.mask = 1;
    attr.attr.id = GPIO_V2_LINE_ATTR_ID_DEBOUNCE;
    // Microseconds, rounded up so that a sub-microsecond request is not silently none.
    attr.attr.debounce_period_us = static_cast<std::uint32_t>((spec.debounce.count() + 999) / 1000);
  }
  request.event_buffer_size = event_buffer_size;
  return request;
}

GpioSource::GpioSource(GpioDevices& devices, const std::vector<ChannelSpec>& channels,
                       GpioSourceOptions options)
    : options_(std::move(options)) {
  if (channels.empty())
    throw core::Error(core::ErrorKind::usage, "no channel to capture: give --channel NAME=CHIP:LINE");
  epoll_fd_.reset(::epoll_create1(EPOLL_CLOEXEC));
  if (!epoll_fd_) throw core::Error(core::ErrorKind::io, fmt::format("epoll: {}", std::strerror(errno)));
  // A throw below releases what was requested: the channels' requests and the epoll descriptor are
  // members.
  for (const auto& spec : channels) {
    for (const auto& other : channels_)
      if (other.spec.name == spec.name)
        throw core::Error(core::ErrorKind::usage,
                          fmt::format("channel '{}' is configured twice", spec.name));
    Channel channel;
    channel.spec = spec;
    channel.chip = find_chip(devices, spec.chip);
    const auto offset = find_line(devices, channel.chip, spec.line);
    for (const auto& other : channels_)
      if (other.chip.path == channel.chip.path && other.line.offset == offset)
        throw core::Error(core::ErrorKind::usage,
                          fmt::format("channels '{}' and '{}' are the same line {} of {}", other.spec.name,
                                      spec.name, offset, channel.chip.name));
    channel.consumer = (options_.consumer_prefix + spec.name).substr(0, GPIO_MAX_NAME_SIZE - 1);
    auto request = make_input_request(spec, offset, channel.consumer, options_.event_buffer_size);
    try {
      channel.line = devices.line_info(channel.chip.path, offset);
      channel.request = devices.request_lines(channel.chip.path, request);
      channel.line = devices.line_info(channel.chip.path, offset);  // with the settings now in force
    } catch (const std::system_error& e) {
      throw explain_gpio_error(e, devices, channel.chip, offset);
    }
    epoll_event ev{};
    ev.events = EPOLLIN;
    if (::epoll_ctl(epoll_fd_.get(), EPOLL_CTL_ADD, channel.request->fd(), &ev) < 0)
      throw core::Error(core::ErrorKind::io, fmt::format("epoll: {}", std::strerror(errno)));
    channels_.push_back(std::move(channel));
  }
}

GpioSource::~GpioSource() {
  channels_.clear();  // the line requests first, then the epoll descriptor (a member)
}

void GpioSource::read_channel(Channel& channel, ReadResult& out, std::size_t max_events) {
  const auto clock = stored_clock(channel.spec.clock);
  while (max_events > 0) {
    const auto want = std::min(max_events, scratch_.size());
    std::size_t n = 0;
    try {
      n = channel.request->read_events(std::span(scratch_.data(), want));
    } catch (const std::system_error& e) {
      throw core::Error(core::ErrorKind::io, fmt::format("channel '{}': {}", channel.spec.name, e.what()));
    }
    for (std::size_t i = 0; i < n; ++i) {
      const auto& raw = scratch_[i];
      if (const auto gap = channel.seqno.observe(raw.seqno))
        out.gaps.push_back({channel.spec.name, "seqno_gap", gap->first, gap->count});
      // With one line per request line_seqno moves with seqno: its gaps are the same loss, so they
      // are tracked (to catch a kernel that numbers differently) but reported only if they differ.
      const auto line_gap = channel.line_seqno.observe(raw.line_seqno);
      if (line_gap && channel.line_seqno.missing_total() > channel.seqno.missing_total())
        out.gaps.push_back({channel.spec.name, "line_seqno_gap", line_gap->first, line_gap->count});
      // Built in place: in a reused ReadResult (the recorder's) this allocates nothing for names of
      // up to 15 bytes (the strings' own buffer).
      auto& event = out.events.emplace_back();
      event.node = options_.node;
      event.channel = channel.spec.name;
      event.edge = raw.id == GPIO_V2_LINE_EVENT_RISING_EDGE ? core::Edge::rising : core::Edge::falling;
      event.time = core::TimePoint::from_ns(clock, static_cast<std::int64_t>(raw.timestamp_ns));
      event.seqno = raw.seqno;
      event.line_seqno = raw.line_seqno;
    }
    max_events -= n;
    if (n < want) break;
  }
}

void GpioSource::read(ReadResult& out, std::size_t max_events) {
  const auto start = out.events.size();
  for (std::size_t k = 0; k < channels_.size(); ++k) {
    const auto used = out.events.size() - start;
    if (used >= max_events) break;
    read_channel(channels_[(next_ + k) % channels_.size()], out, max_events - used);
  }
  next_ = (next_ + 1) % channels_.size();
}

std::vector<std::string> GpioSource::describe() const {
  std::vector<std::string> lines;
  for (const auto& c : channels_) {
    lines.push_back(fmt::format(
        "{}: {} ({}) line {}{}, {} edges, bias {}{}, {} clock, debounce {}, refractory {}, consumer '{}'",
        c.spec.name, c.chip.path, c.chip.label, c.line.offset,
        c.line.name.empty() ? "" : " '" + c.line.name + "'", to_string(c.spec.edges), to_string(c.spec.bias),
        c.spec.active_low ? ", active-low" : "", to_string(c.spec.clock),
        c.spec.debounce.count() > 0 ? core::format_duration(c.spec.debounce) : "none",
        c.spec.refractory.count() > 0 ? core::format_duration(c.spec.refractory) : "none", c.consumer));
  }
  return lines;
}

std::vector<std::string> GpioSource::channels() const {
  std::vector<std::string> names;
  for (const auto& c : channels_) names.push_back(c.spec.name);
  return names;
}

std::vector<std::string> GpioSource::consumers() const {
  std::vector<std::string> labels;
  for (const auto& c : channels_) labels.push_back(c.consumer);
  return labels;
}

std::vector<std::string> GpioSource::warnings() const {
  std::vector<std::string> out;
  for (const auto& c : channels_) {
    if (c.spec.debounce.count() > 0)
      out.push_back(fmt::format(
          "channel '{}': kernel debounce {} is on: the kernel then stamps each edge in a work item after the "
          "debounce period instead of in the hard interrupt, so every timestamp is late; prefer --debounce 0 "
          "with --refractory",
          c.spec.name, core::format_duration(c.spec.debounce)));
    if (c.spec.clock != EventClock::realtime)
      out.push_back(fmt::format("channel '{}': {} timestamps cannot be compared with another board's",
                                c.spec.name, to_string(c.spec.clock)));
  }
  return out;
}

}  // namespace m2mlat::capture
