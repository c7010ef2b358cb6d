// The pulse generator for the synchronisation test: toggles an output line every `period` (500 ms
// in the reference rig) for a count of edges or a duration. Each deadline is absolute on
// CLOCK_REALTIME (clock_nanosleep with TIMER_ABSTIME), so errors do not accumulate from edge to edge;
// the first edge falls on a multiple of the period, so two generators (or a generator and a
// reader) agree on the schedule. Each edge's commanded time is read just before the ioctl that
// sets the line, and how late that was after its deadline is kept; the clock is read again just
// after the ioctl returned, so [commanded, after] bounds when the line changed.
//
// The same generator drives the glass-to-glass LED (`m2mlat led`): with `on_for` the line goes high
// at each period's deadline and low `on_for` later (a flash), and set() switches it when something
// else decides (led_trigger.hpp: a command, an input edge).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

struct PulseOptions {
  std::string chip;                                        // path, name or label
  std::string line;                                        // offset or name
  core::Duration period = std::chrono::milliseconds(500);  // between two edges (a toggle each period)
  std::uint64_t count = 0;                                 // edges to make (0: until the duration or a stop)
  core::Duration duration{0};                              // stop after this long (0: no limit)
  // 0: a toggle each period (the synchronisation pulse). > 0: high at each period's deadline and low
  // this long after it (an LED's flash); must be shorter than the period.
  core::Duration on_for{0};
  std::string consumer = "m2mlat-pulse";
  // Now on CLOCK_REALTIME, ns; empty = the real clock. Tests use the real one too (short periods).
  std::function<std::int64_t()> now;
};

struct PulseEdge {
  std::uint64_t index = 0;  // 0-based
  core::Edge edge = core::Edge::rising;
  core::TimePoint deadline;   // when it was due (CLOCK_REALTIME)
  core::TimePoint commanded;  // when the set-values ioctl was issued (CLOCK_REALTIME)
  core::TimePoint after;      // the clock read just after the ioctl returned (CLOCK_REALTIME)
  // How long the ioctl took: the line changed somewhere in [commanded, after].
  core::Duration bound() const { return after - commanded; }
};

// The event a commanded edge is stored as: channel "pulse", its edge, the commanded time, flags
// commanded and no-kernel-seqno (the generator makes edges; no kernel numbered them).
core::Event commanded_event(const std::string& node, const PulseEdge& edge);
// The event an LED switch is stored as: channel `channel`, its edge, flags commanded and
// no-kernel-seqno, and as its time the middle of [commanded, after] (then off by at most half the
// bound either way; docs/capture.md "m2mlat led").
core::Event led_event(const std::string& node, const std::string& channel, const PulseEdge& edge);

struct PulseSummary {
  std::uint64_t edges = 0;
  core::Duration max_late{0};    // largest commanded - deadline
  core::Duration total_late{0};  // sum, for the mean
  std::string stop_reason;       // "count", "duration", or the stop's name
};

class PulseGenerator {
 public:
  // Finds the chip and line and requests it as an output, low. Throws core::Error with the fix.
  PulseGenerator(GpioDevices& devices, PulseOptions options);
  ~PulseGenerator();
  PulseGenerator(const PulseGenerator&) = delete;
  PulseGenerator& operator=(const PulseGenerator&) = delete;

  // Toggles until the count, the duration, or `stop_fd` polls readable (-1: never); `on_edge` sees
  // each edge after it was made. The line is left low.
  PulseSummary run(int stop_fd, const std::function<void(const PulseEdge&)>& on_edge,
                   const std::function<std::string()>& stop_name = {});
  std::string describe() const;

  // Sets the line high or low now, reading the clock just before and just after the ioctl. `index`
  // and `deadline` are passed through to the edge (a triggered switch's deadline is when its
  // trigger asked for it). Throws core::Error(io) naming the line if the ioctl fails.
  PulseEdge set(bool high, std::uint64_t index, core::TimePoint deadline);
  bool high() const { return level_; }

 private:
  PulseOptions options_;
  ChipInfo chip_;
  std::uint32_t offset_ = 0;
  std::unique_ptr<LineRequest> request_;
  bool level_ = false;  // the line's value as last set
};

}  // namespace m2mlat::capture
