// The pulse generator for the synchronisation test: toggles an output line every `period` (500 ms
// in the reference rig) for a count of edges or a duration. Each deadline is absolute on
// CLOCK_REALTIME (clock_nanosleep with TIMER_ABSTIME), so errors do not accumulate from edge to edge;
// the first edge falls on a multiple of the period, so two generators (or a generator and a
// reader) agree on the schedule. Each edge's commanded time is read just before the ioctl that
// sets the line, and how late that was after its deadline is kept.
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
  std::string consumer = "m2mlat-pulse";
  // Now on CLOCK_REALTIME, ns; empty = the real clock. Tests use the real one too (short periods).
  std::function<std::int64_t()> now;
};

struct PulseEdge {
  std::uint64_t index = 0;  // 0-based
  core::Edge edge = core::Edge::rising;
  core::TimePoint deadline;   // when it was due (CLOCK_REALTIME)
  core::TimePoint commanded;  // when the set-values ioctl was issued (CLOCK_REALTIME)
};

// The event a commanded edge is stored as: channel "pulse", its edge, the commanded time, flags
// commanded and no-kernel-seqno (the generator makes edges; no kernel numbered them).
core::Event commanded_event(const std::string& node, const PulseEdge& edge);

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

 private:
  PulseOptions options_;
  ChipInfo chip_;
  std::uint32_t offset_ = 0;
  std::unique_ptr<LineRequest> request_;
};

}  // namespace m2mlat::capture
