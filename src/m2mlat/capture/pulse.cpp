// Absolute deadlines on CLOCK_REALTIME; poll(2) on the stop descriptor until just before each
// deadline, then clock_nanosleep to it exactly.
#include "m2mlat/capture/pulse.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <time.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "m2mlat/capture/chip_lookup.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

namespace {

constexpr std::int64_t kNsPerSec = 1'000'000'000;

}  // namespace

core::Event commanded_event(const std::string& node, const PulseEdge& edge) {
  core::Event event;
  event.node = node;
  event.channel = "pulse";
  event.edge = edge.edge;
  event.time = edge.commanded;
  event.flags = core::kFlagCommanded | core::kFlagNoKernelSeqno;
  return event;
}

core::Event led_event(const std::string& node, const std::string& channel, const PulseEdge& edge) {
  core::Event event = commanded_event(node, edge);
  event.channel = channel;
  event.time = edge.commanded + edge.bound() / 2;
  return event;
}

PulseGenerator::PulseGenerator(GpioDevices& devices, PulseOptions options) : options_(std::move(options)) {
  if (options_.period.count() <= 0) throw core::Error(core::ErrorKind::usage, "--period must be positive");
  if (options_.on_for.count() < 0 || (options_.on_for.count() > 0 && options_.on_for >= options_.period))
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("--on-for ({}) must be positive and shorter than --period ({})",
                    core::format_duration(options_.on_for), core::format_duration(options_.period)));
  if (!options_.now) options_.now = [] { return core::now_ns(CLOCK_REALTIME); };
  chip_ = find_chip(devices, options_.chip);
  offset_ = find_line(devices, chip_, options_.line);
  gpio_v2_line_request request{};
  request.offsets[0] = offset_;
  request.num_lines = 1;
  const auto label = options_.consumer.substr(0, sizeof request.consumer - 1);
  std::memcpy(request.consumer, label.data(), label.size());
  request.config.flags = GPIO_V2_LINE_FLAG_OUTPUT;
  auto& attr = request.config.attrs[request.config.num_attrs++];
  attr.mask = 1;
  attr.attr.id = GPIO_V2_LINE_ATTR_ID_OUTPUT_VALUES;
  attr.attr.values = 0;  // start low
  try {
    request_ = devices.request_lines(chip_.path, request);
  } catch (const std::system_error& e) {
    throw explain_gpio_error(e, devices, chip_, offset_);
  }
}

PulseGenerator::~PulseGenerator() {
  try {
    if (request_) request_->set_values(0, 1);
  } catch (const std::system_error&) {  // the line is released right after anyway
  }
}

std::string PulseGenerator::describe() const {
  const auto schedule = options_.on_for.count() > 0
                            ? fmt::format("on for {} every {}", core::format_duration(options_.on_for),
                                          core::format_duration(options_.period))
                            : fmt::format("a toggle every {}", core::format_duration(options_.period));
  return fmt::format("{} ({}) line {}, {}{}", chip_.path, chip_.label, offset_, schedule,
                     options_.count > 0 ? fmt::format(", {} edges", options_.count) : std::string());
}

PulseEdge PulseGenerator::set(bool high, std::uint64_t index, core::TimePoint deadline) {
  const std::int64_t before = options_.now();
  try {
    request_->set_values(high ? 1 : 0, 1);
  } catch (const std::system_error& e) {
    throw core::Error(core::ErrorKind::io,
                      fmt::format("output line {} of {}: {}", offset_, chip_.name, e.what()));
  }
  const std::int64_t after = options_.now();
  level_ = high;
  return {index, high ? core::Edge::rising : core::Edge::falling, deadline,
          core::TimePoint::from_ns(core::Clock::realtime, before),
          core::TimePoint::from_ns(core::Clock::realtime, after)};
}

PulseSummary PulseGenerator::run(int stop_fd, const std::function<void(const PulseEdge&)>& on_edge,
                                 const std::function<std::string()>& stop_name) {
  const std::int64_t period = options_.period.count();
  // The first edge on a multiple of the period, at least 100 ms (and a period) from now.
  const std::int64_t start = options_.now();
  const std::int64_t first = ((start + 100'000'000) / period + 1) * period;
  const std::int64_t end = options_.duration.count() > 0 ? start + options_.duration.count() : INT64_MAX;
  PulseSummary summary;
  const std::int64_t on_for = options_.on_for.count();
  for (std::uint64_t k = 0;; ++k) {
    if (options_.count > 0 && k >= options_.count) {
      summary.stop_reason = "count";
      break;
    }
    // A toggle each period, or (a flash) high at each period's deadline and low on_for after it.
    const auto n = static_cast<std::int64_t>(k);
    const std::int64_t deadline = on_for > 0 ? first + n / 2 * period + n % 2 * on_for : first + n * period;
    if (deadline > end) {
      summary.stop_reason = "duration";
      break;
    }
    // Wait for a stop until 2 ms before the deadline; then sleep to the deadline itself.
    bool stopped = false;
    for (;;) {
      const std::int64_t left = deadline - options_.now() - 2'000'000;
      if (left <= 0) break;
      pollfd fd{stop_fd, POLLIN, 0};
      const int ready = ::poll(&fd, 1, static_cast<int>(std::min<std::int64_t>(left / 1'000'000 + 1, 1000)));
      if (ready < 0 && errno != EINTR)
        throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
      if (stop_fd >= 0 && ready > 0 && (fd.revents & POLLIN) != 0) {
        stopped = true;
        break;
      }
    }
    if (stopped) {
      summary.stop_reason = stop_name ? stop_name() : "stop";
      if (summary.stop_reason.empty()) summary.stop_reason = "stop";
      break;
    }
    core::sleep_until_ns(CLOCK_REALTIME, deadline);
    const auto edge = set(!level_, k, core::TimePoint::from_ns(core::Clock::realtime, deadline));
    const core::Duration late = edge.commanded - edge.deadline;
    summary.max_late = std::max(summary.max_late, late);
    summary.total_late += late;
    ++summary.edges;
    if (on_edge) on_edge(edge);
  }
  return summary;
}

}  // namespace m2mlat::capture
