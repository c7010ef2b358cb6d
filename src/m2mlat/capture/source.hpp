// The capture source interface: where a recorder's edge events come from. A source hands over the
// events it has (never waiting inside read) and the gaps it could see in the kernel's sequence
// numbers; the recorder waits on its pollable descriptor. Implementations: GpioSource (the Linux
// GPIO character device, uAPI v2), KmsgSource (the reference rig's kernel-module log lines),
// SimSource (the simulated rig), each testable with an in-process twin.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::capture {

// Events known to be missing, from a jump in a sequence number.
struct Gap {
  std::string channel;              // the channel it was seen on; empty for a node-wide counter (kmsg)
  std::string kind;                 // "seqno_gap", "line_seqno_gap" or "kmsg_gap" (store::kLossKinds)
  std::uint64_t first_missing = 0;  // first missing number of that counter
  std::uint64_t count = 0;          // how many numbers are missing (at least 1)
  friend bool operator==(const Gap&, const Gap&) = default;
};

struct ReadResult {
  std::vector<core::Event> events;  // in the order the kernel reported them
  std::vector<Gap> gaps;            // each reported where it was detected, before the event after it
  // Readings of the clock that stamped the events, where the source has its own (the simulated
  // rig's daemons); a real board's come from the recorder's clock monitor instead. session_id unset.
  std::vector<store::ClockSample> clock_samples;
  bool finished = false;  // the source has nothing more, ever (a simulated run's end)
  void clear() {
    events.clear();
    gaps.clear();
    clock_samples.clear();
    finished = false;
  }
};

class Source {
 public:
  virtual ~Source() = default;
  // Appends to `out` up to `max_events` events that are ready, without blocking (none is fine).
  virtual void read(ReadResult& out, std::size_t max_events) = 0;
  // A descriptor that polls readable when read() has something; -1 if the source cannot be polled
  // (a followed file, a paced simulation): the caller then calls read() every poll_interval().
  virtual int fd() const = 0;
  virtual core::Duration poll_interval() const { return std::chrono::milliseconds(20); }
  // One line per channel for the terminal and the session's record: "wheel: /dev/gpiochip0 line 16 ...".
  virtual std::vector<std::string> describe() const = 0;
  // The channels this source produces, in configuration order (more may appear while reading).
  virtual std::vector<std::string> channels() const = 0;
  // What the user should hear about after the run (lines passed over, ...); none by default.
  virtual std::vector<std::string> notes() const { return {}; }
};

}  // namespace m2mlat::capture
