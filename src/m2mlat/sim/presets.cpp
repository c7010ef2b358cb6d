// The named scenarios: each a few changes to the default RigConfig (which is static_wifi).
#include "m2mlat/sim/presets.hpp"

#include <fmt/format.h>

#include <array>

#include "m2mlat/core/error.hpp"

namespace m2mlat::sim {

using namespace std::chrono_literals;

namespace {
constexpr std::array<PresetInfo, 5> kPresets{{
    {"static_wifi",
     "vehicle standing, commands over WiFi, clocks co-referenced (study: median 874 ms, IQR 198)"},
    {"static_5g", "vehicle standing, commands over 5G, clocks co-referenced (study: median 931 ms, IQR 105)"},
    {"dynamic_co_referenced",
     "vehicle driving, commands over 5G, clocks co-referenced (study: median 768 ms, IQR 142)"},
    {"dynamic_autonomous",
     "vehicle driving, commands over 5G, clocks autonomous (study: median 815 ms, IQR 146)"},
    {"stalls",
     "static_5g with link stalls of 1-6 s, 2 a minute (handovers): queued commands arrive in a burst"},
}};
}  // namespace

std::span<const PresetInfo> presets() { return kPresets; }

RigConfig preset(std::string_view name) {
  RigConfig config;
  config.scenario = std::string(name);
  if (name == "static_wifi") return config;
  // Each scenario is a separate drive in the study, so each preset has its own seed.
  if (name == "static_5g") {
    config.seed = 2;
    config.network = network_profile("5g");
    return config;
  }
  if (name == "dynamic_co_referenced" || name == "dynamic_autonomous") {
    config.seed = name == "dynamic_co_referenced" ? 3 : 4;
    config.network = network_profile("5g");
    config.vehicle.moving_probability = 1;
    if (name == "dynamic_autonomous") {
      // Each board to its own servers: the two path asymmetries do not cancel.
      config.sync = sync_profile("autonomous");
      config.cause_clock.sync_bias = 120us;
      config.effect_clock.sync_bias = -120us;
    }
    return config;
  }
  if (name == "stalls") {
    // Not a scenario of the study: the link failure its matcher must survive (docs/simulator.md).
    config.seed = 5;
    config.network = network_profile("5g");
    config.network.stall_per_minute = 2;
    return config;
  }
  throw core::Error(
      core::ErrorKind::usage,
      fmt::format("unknown scenario '{}' (expected static_wifi, static_5g, dynamic_co_referenced, "
                  "dynamic_autonomous or stalls)",
                  name));
}

}  // namespace m2mlat::sim
