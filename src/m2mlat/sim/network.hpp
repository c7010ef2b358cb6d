// Network profiles: the one-way delay a steering command sees between the operator station and the
// vehicle, and how often it is lost. A lost command packet is not retransmitted: the motion reaches
// the vehicle with the next command period's packet (the station sends the wheel angle every period).
// A stall (a link that stops for seconds: a handover, a congested cell) delivers nothing while it
// lasts; the packets sent meanwhile wait in the queue and arrive in order when it ends, one every
// stall_drain as the link drains. docs/simulator.md ("Network stalls") describes what the vehicle does.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "m2mlat/sim/distribution.hpp"

namespace m2mlat::sim {

struct NetworkProfile {
  std::string name;              // "wifi", "5g", "wired", or "custom" after an override changed it
  DurationDist delay;            // one-way delay of a delivered packet: base + jitter
  double burst_probability = 0;  // chance that a packet also waits out a burst (power save, retries)
  DurationDist burst;            // the extra delay of a burst
  double loss_probability = 0;   // chance that a command packet is lost (independent per packet)
  double stall_per_minute = 0;   // stalls per minute of run (a Poisson process; 0: none)
  DurationDist stall = uniform(std::chrono::seconds{1}, std::chrono::seconds{5});  // length: [1, 6) s
  core::Duration stall_drain = std::chrono::milliseconds{2};  // queued packets arrive this far apart

  friend bool operator==(const NetworkProfile&, const NetworkProfile&) = default;
};

struct NetworkInfo {
  std::string_view name;
  std::string_view description;  // one line
};

// The named profiles with a line on each.
std::span<const NetworkInfo> network_profiles();
// The profile called `name`; throws core::Error(usage) listing the known names.
NetworkProfile network_profile(std::string_view name);

void validate(const NetworkProfile& network, std::string_view field);

}  // namespace m2mlat::sim
