// The named scenarios of the simulated rig. Each resembles one scenario of the reference field study
// (a teleoperated vehicle steered over WiFi or 5G, standing or driving, with the boards' clocks
// co-referenced or autonomous); docs/simulator.md compares their statistics with the study's.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/sim/rig_config.hpp"

namespace m2mlat::sim {

struct PresetInfo {
  std::string_view name;
  std::string_view description;  // one line
};

// static_wifi (the default), static_5g, dynamic_co_referenced, dynamic_autonomous; and stalls (a 5G
// link that stops for seconds now and then: not a scenario of the study).
std::span<const PresetInfo> presets();
// The preset called `name`; throws core::Error(usage) listing the names.
RigConfig preset(std::string_view name);

}  // namespace m2mlat::sim
