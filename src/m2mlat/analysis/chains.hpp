// The full loop from raw data: per event the chain station onset -> vehicle onset (M2M) -> LED on ->
// photo edge (G2G), E2E = M2M + G2G, and each side's motion duration (end - onset).
//
// Onsets come from the raw gyroscope traces through an onset detector (onset/detectors.hpp, "flank"
// by default). Pairing is automatic: station onsets to vehicle onsets by the matcher
// (pairing/matcher.hpp; M2M may be negative in the baseline, so its window opens before zero), LED
// stamps to photo edges by the matcher too, and each vehicle onset joined to the first unused LED
// write within [onset - join_before, onset + join_after] (the vehicle board sets the LED when it sees
// its wheel move: after the true onset, by its online detector's delay; an offline detector's onset
// may be later still). What the LED's lag after the onset
// is (led_lag_ns) is not part of E2E: the rig defines E2E = M2M + G2G, as if the LED were lit at the
// onset itself; the lag is kept per chain so that it can be seen.
//
// A chain that lacks a link is kept and counted by its first missing link (ChainGap); the quantities
// it cannot give are "missing" in the summaries. Nothing is dropped silently.
//
// Per-chain standard uncertainty (k = 1), ns:
//   M2M: sqrt(u_sync(station, vehicle)^2 + u_onset_station^2 + u_onset_vehicle^2)
//   G2G: sqrt(u_sync(vehicle, station)^2 + (led_bound / sqrt 3)^2 + kernel_u^2 + photo_u^2); no sync
//        term on one board (single_board)
//   E2E: the same without any sync term: the vehicle clock's error enters the vehicle onset and the LED
//        stamp alike, the station clock's the station onset and the photo edge alike, and both cancel
//        in M2M + G2G.
// u_sync is the clock part of analysis/uncertainty.hpp's model (pair_uncertainty with the kernel and
// calibration terms set to zero); unknown (no clock samples, unsynchronised) leaves that u unset.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/onset/motion.hpp"
#include "m2mlat/pairing/matcher.hpp"

namespace m2mlat::sim {
struct FullLoopRun;
}

namespace m2mlat::analysis {

struct LedWrite {
  std::int64_t stamp_ns = 0;  // the middle of [before, after] on the vehicle board's clock, ns
  std::int64_t bound_ns = 0;  // half-width of [before, after], ns
};

struct ChainInput {
  core::RateTrace station_trace, vehicle_trace;  // raw; both empty: LED -> photo alone (single board)
  std::vector<LedWrite> led;                     // in time order
  std::vector<std::int64_t> photo_ns;            // the station board's photo edges, in time order
  ClockTrack station_clock, vehicle_clock;       // the boards' clock samples (may be empty)
  bool single_board = false;                     // LED and photo on one board: no sync term in G2G
};

struct ChainOptions {
  std::string detector = "flank";  // onset::detector name
  pairing::MatchOptions m2m;       // station onset -> vehicle onset
  pairing::MatchOptions g2g;       // LED -> photo edge
  // The LED write joined to a vehicle onset lies in [onset - join_before, onset + join_after], ns: the
  // board's own online detection sets it a little after the true onset, and an offline detector's
  // onset may lag that (the reference detector's fixed threshold: hundreds of ms on slow motions).
  core::Duration join_before{1'000'000'000}, join_after{200'000'000};
  UncertaintyOptions uncertainty;  // the sync term's model; kernel_u: the photo edge's interrupt stamp
  core::Duration photo_u{10'000};  // the phototransistor + comparator response, standard uncertainty, ns
  ChainOptions();                  // the windows above: M2M in [-0.5 s, 2 s], G2G in [0, 2 s]
};

// Why a chain is incomplete: its first missing link. Keys: "no_vehicle_onset", "no_station_onset",
// "no_led", "no_photo", "led_unjoined" (an LED write near no vehicle onset), "photo_unmatched",
// "flagged_pair" (all links there, but the matcher was not sure of the M2M or the G2G pair: its
// quantities are left out, as flagged pairs are everywhere; docs/matcher.md).
enum class ChainGap : std::uint8_t {
  no_vehicle_onset,
  no_station_onset,
  no_led,
  no_photo,
  led_unjoined,
  photo_unmatched,
  flagged_pair
};
inline constexpr std::size_t kChainGaps = 7;
std::string_view key(ChainGap gap);

struct Chain {
  std::optional<std::size_t> station, vehicle, led, photo;  // indices: onsets, ChainInput::led, photo_ns
  std::optional<std::int64_t> station_onset_ns, vehicle_onset_ns, led_ns, photo_ns;  // board clocks
  std::optional<std::int64_t> led_lag_ns;                // LED stamp - vehicle onset (not in E2E), ns
  std::optional<ChainGap> gap;                           // unset: complete
  bool m2m_flagged = false, g2g_flagged = false;         // the matcher's pair had a PairFlag reason
  std::array<LoopValue, kLoopQuantities.size()> values;  // by LoopQuantity
  // Standard uncertainty (k = 1) of M2M, G2G, E2E, ns; unset where the value or its clock state is unknown.
  std::array<std::optional<std::int64_t>, 3> u_ns;
};

struct ChainResult {
  std::string detector;
  std::vector<onset::Motion> station_onsets, vehicle_onsets;
  std::vector<Chain> chains;                         // in time order
  std::array<std::size_t, kChainGaps> incomplete{};  // by ChainGap
  FullLoopResult loop;                               // the summaries, as for the full-loop rig's files
};

// Throws core::Error(usage) for an unknown detector, core::Error(data) for a malformed trace.
ChainResult build_chains(const ChainInput& input, const ChainOptions& options,
                         const stats::SummaryOptions& summary, std::string scenario);

// The simulator's full-loop run as the chains' input: its traces, LED writes, photo edges, and each
// board's clock samples (one a second, est_error = sync_max / sqrt(3), max_error = sync_max).
ChainInput chain_input(const sim::FullLoopRun& run);

}  // namespace m2mlat::analysis
