// The named network profiles. The figures are chosen so that, with the rig's actuator, the scenarios
// resemble the reference field study (docs/simulator.md shows how): a WiFi link that is fast when
// it is quiet but often holds packets for hundreds of milliseconds, and a cellular 5G path through
// the operator's core network that is slower but steady.
#include "m2mlat/sim/network.hpp"

#include <fmt/format.h>

#include <array>

#include "m2mlat/core/error.hpp"

namespace m2mlat::sim {

using namespace std::chrono_literals;

namespace {
constexpr std::array<NetworkInfo, 3> kProfiles{{
    {"wifi", "WiFi link: ~13 ms when quiet, 35% of packets held up to 500 ms (power save, retries), 3% loss"},
    {"5g", "5G cellular path via the operator core: ~105 ms one way, little jitter, 1% loss"},
    {"wired", "Ethernet LAN: ~0.25 ms one way, no loss"},
}};
}  // namespace

std::span<const NetworkInfo> network_profiles() { return kProfiles; }

NetworkProfile network_profile(std::string_view name) {
  if (name == "wifi") {
    DurationDist burst = uniform(0ms, 500ms);
    return {"wifi", lognormal(3ms, 10ms, 0.8), 0.35, burst, 0.03};
  }
  if (name == "5g") return {"5g", lognormal(95ms, 10ms, 0.5), 0, constant(0ms), 0.01};
  if (name == "wired") return {"wired", lognormal(200us, 50us, 0.5), 0, constant(0ms), 0};
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("unknown network profile '{}' (expected wifi, 5g or wired)", name));
}

void validate(const NetworkProfile& network, std::string_view field) {
  validate(network.delay, fmt::format("{}.delay", field));
  validate(network.burst, fmt::format("{}.burst", field));
  if (!(network.burst_probability >= 0 && network.burst_probability <= 1))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("simulator setting '{}.burst_probability': must be in [0, 1]", field));
  if (!(network.loss_probability >= 0 && network.loss_probability <= 0.9))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("simulator setting '{}.loss_probability': must be in [0, 0.9]", field));
  if (!(network.stall_per_minute >= 0 && network.stall_per_minute <= 60))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("simulator setting '{}.stall_per_minute': must be in [0, 60]", field));
  validate(network.stall, fmt::format("{}.stall", field));
  if (network.stall_drain < 1us)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("simulator setting '{}.stall_drain': must be at least 1us", field));
}

}  // namespace m2mlat::sim
