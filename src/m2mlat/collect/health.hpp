// The coordinator's view of each agent's health: when it last answered, how fast events arrive,
// what it reports lost, and its clock state. Pullers write it (one NodeTracker per agent, updated
// from their own thread); the terminal view and the dashboard read thread-safe snapshots.
//
// State: ok while the agent answered within --stale-after; stale when it has not answered for
// longer; unreachable after a failed request (until the next success).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "m2mlat/core/event.hpp"

namespace m2mlat::collect {

enum class NodeState : std::uint8_t { ok = 0, stale = 1, unreachable = 2 };
std::string_view to_string(NodeState state);  // "ok" | "stale" | "unreachable"

// One agent as the coordinator sees it: a value, copied out of the tracker under its lock.
struct NodeHealth {
  std::string node;  // the agent's node name from /v1/status ("" until the first answer)
  std::string url;   // the agent's base URL as given with --agent
  core::Role role = core::Role::observer;
  NodeState state = NodeState::unreachable;
  std::int64_t last_contact_ns = 0;  // CLOCK_REALTIME of the last successful request, ns; 0 = never
  double events_per_s = 0.0;         // events stored at the coordinator per second, over the last 10 s
  std::uint64_t events = 0;          // events of this agent stored by this coordinator run
  std::int64_t cursor_seq = 0;       // the agent's seq up to which the campaign store holds its events
  std::int64_t agent_last_seq =
      0;                   // the agent's last committed seq at its last status (lag = this - cursor_seq)
  std::uint64_t lost = 0;  // events the agent reports lost (/v1/status "lost")
  std::int64_t clock_offset_ns = 0;     // the agent's latest clock sample: offset from its reference, ns
  std::int64_t clock_max_error_ns = 0;  // ... and its maximum error bound, ns (0 with no sample)
  bool synchronised = false;            // ... and whether its clock was synchronised
  bool has_clock = false;               // false while the agent has reported no clock sample
  std::string last_error;               // the last pull error ("" if none since the last success)
};

// The clock part of an agent's status.
struct ClockState {
  std::int64_t offset_ns = 0;     // offset from the reference, ns (positive = ahead)
  std::int64_t max_error_ns = 0;  // maximum error bound, ns
  bool synchronised = false;
};

// The health of one agent, updated by its puller and read by anyone. Times are CLOCK_REALTIME ns
// passed in by the caller, so that tests can drive it with their own clock.
class NodeTracker {
 public:
  NodeTracker(std::string url, std::chrono::nanoseconds stale_after);

  // A request succeeded at now_ns.
  void contact(std::int64_t now_ns);
  // The agent's /v1/status answer at now_ns; counts as contact.
  void status(std::string node, core::Role role, std::uint64_t lost, std::int64_t last_seq,
              std::optional<ClockState> clock, std::int64_t now_ns);
  // `count` events of this agent were stored at now_ns, up to the agent's seq `cursor_seq`.
  void stored(std::uint64_t count, std::int64_t cursor_seq, std::int64_t now_ns);
  // The campaign store's cursor for this agent, as read at the start of a pull.
  void cursor(std::int64_t cursor_seq);
  // A request failed at now_ns: the node is unreachable until the next contact.
  void failed(std::string message, std::int64_t now_ns);

  // The health at now_ns (state and rate are computed for that instant).
  NodeHealth snapshot(std::int64_t now_ns) const;

  // The window over which events_per_s is averaged.
  static constexpr std::int64_t kRateWindowNs = 10'000'000'000;

 private:
  void expire(std::int64_t now_ns) const;

  mutable std::mutex mutex_;
  NodeHealth health_;
  std::chrono::nanoseconds stale_after_;
  bool failed_ = true;         // no successful request yet, or the last one failed
  std::int64_t first_ns_ = 0;  // the first contact (the rate window is shorter before 10 s)
  // (time ns, events stored) per storing pull within the rate window
  mutable std::deque<std::pair<std::int64_t, std::uint64_t>> recent_;
  mutable std::uint64_t recent_sum_ = 0;
};

}  // namespace m2mlat::collect
