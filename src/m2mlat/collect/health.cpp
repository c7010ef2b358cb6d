// Per-agent health: contact times, a sliding 10 s event rate, the agent's losses and clock state.
#include "m2mlat/collect/health.hpp"

#include "m2mlat/core/clock_read.hpp"

#include <time.h>

#include <algorithm>

namespace m2mlat::collect {

std::string_view to_string(NodeState state) {
  switch (state) {
    case NodeState::ok: return "ok";
    case NodeState::stale: return "stale";
    case NodeState::unreachable: return "unreachable";
  }
  return "unreachable";
}

NodeTracker::NodeTracker(std::string url, std::chrono::nanoseconds stale_after) : stale_after_(stale_after) {
  health_.url = std::move(url);
}

void NodeTracker::contact(std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  if (first_ns_ == 0) first_ns_ = now_ns;
  health_.last_contact_ns = now_ns;
  health_.last_error.clear();
  failed_ = false;
}

void NodeTracker::status(std::string node, core::Role role, std::uint64_t lost, std::int64_t last_seq,
                         std::optional<ClockState> clock, std::int64_t now_ns) {
  contact(now_ns);
  std::lock_guard lock(mutex_);
  health_.node = std::move(node);
  health_.role = role;
  health_.lost = lost;
  health_.agent_last_seq = last_seq;
  health_.has_clock = clock.has_value();
  if (clock) {
    health_.clock_offset_ns = clock->offset_ns;
    health_.clock_max_error_ns = clock->max_error_ns;
    health_.synchronised = clock->synchronised;
  }
}

void NodeTracker::stored(std::uint64_t count, std::int64_t cursor_seq, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  health_.events += count;
  health_.cursor_seq = cursor_seq;
  if (count > 0) {
    recent_.emplace_back(now_ns, count);
    recent_sum_ += count;
  }
}

void NodeTracker::cursor(std::int64_t cursor_seq) {
  std::lock_guard lock(mutex_);
  health_.cursor_seq = cursor_seq;
}

void NodeTracker::failed(std::string message, std::int64_t /*now_ns*/) {
  std::lock_guard lock(mutex_);
  health_.last_error = std::move(message);
  failed_ = true;
}

void NodeTracker::expire(std::int64_t now_ns) const {
  while (!recent_.empty() && recent_.front().first <= now_ns - kRateWindowNs) {
    recent_sum_ -= recent_.front().second;
    recent_.pop_front();
  }
}

NodeHealth NodeTracker::snapshot(std::int64_t now_ns) const {
  std::lock_guard lock(mutex_);
  expire(now_ns);
  NodeHealth h = health_;
  if (failed_)
    h.state = NodeState::unreachable;
  else if (now_ns - h.last_contact_ns > stale_after_.count())
    h.state = NodeState::stale;
  else
    h.state = NodeState::ok;
  // Before the first 10 s have passed, average over the time since the first contact (at least 1 s,
  // so that a first burst does not read as an absurd rate).
  std::int64_t window = kRateWindowNs;
  if (first_ns_ != 0 && now_ns - first_ns_ < window)
    window = std::max<std::int64_t>(now_ns - first_ns_, 1'000'000'000);
  h.events_per_s = static_cast<double>(recent_sum_) * 1e9 / static_cast<double>(window);
  return h;
}

}  // namespace m2mlat::collect
