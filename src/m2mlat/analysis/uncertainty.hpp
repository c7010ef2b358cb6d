// The uncertainty of each latency sample: one model, the only one (docs/precision.md states it and
// its calibration on the simulator). Every output (stats, pair and export columns, the report, the
// demo's truth check) takes its numbers from here.
//
// A latency is effect_time - cause_time, each stamped by its own board's CLOCK_REALTIME. Its error
// is (effect board's clock error at the effect) - (cause board's clock error at the cause) + (the
// difference of the two interrupt latencies) + (calibration: where on the wheel each sensor fires).
// Per sample two numbers are given, from the measured terms, and a worst-case bound beside them:
//
//   u   = sqrt(u_clock^2 + 2 kernel_u^2 + calibration_u^2)     standard uncertainty (k = 1), GUM
//   U95 = 2 u                                                  expanded uncertainty (k = 2, ~95 %)
//   max_error = max_err_cause(t_cause) + max_err_effect(t_effect) + kernel_max + calibration_max
//               + bounce span (how long the edges dropped as bounces went on after either edge: the
//               pass's edge may be a later one of its cluster)
//
// The clock term. A board's clock sample (store::ClockSample) carries the source's standard
// uncertainty of its offset from its reference (est_error_ns: chrony's RMS offset, chronyd's offset
// sd as the kernel's esterror, the simulated daemon's own figure) and a bound (max_error_ns). Neither
// sees the asymmetry of the path to the reference; it is bounded by root delay / 2 in max_error and
// enters u as path_u per synchronisation path (a stated default). Then:
//   boards synchronised independently:   u_clock^2 = u_C^2 + u_E^2 + 2 path_u^2
//   the effect board follows the cause board (co-referenced: its samples' detail names the cause
//   node as ref_name): the cause's error is common to both stamps and cancels but for how far it
//   moves during the latency dt:         u_clock^2 = u_E^2 + path_u^2 + min(skew_C dt, sqrt(2) u_C)^2
// where skew_C is the cause daemon's reported rate uncertainty (detail "skew_ppm"; 0 if not given).
//   one board stamped both (cause and effect are channels of one node, e.g. single-board
//   glass-to-glass): its offset cancels, synchronised or not; what is left is its drift over the
//   latency dt:                          u_clock = growth_ppm dt / sqrt(3), clock part of max_error
//                                        growth_ppm dt (no unsynchronised flag; a step still flags)
//
// A board's state at time t comes from its two neighbouring clock samples (the last at or before t
// and the first after it). For max_error each neighbour's value is grown by growth_ppm times its
// distance from t (the clock may drift that fast between samples: chrony's maximum error grows the
// same way) and the WORSE of the two is taken: a daemon's bound can jump at a measurement, and the
// worse neighbour stays a bound across the jump. For u each neighbour's value is combined with a
// drift of growth_ppm / sqrt(3) (a frequency error uniform in +-growth_ppm) times the distance, and
// the worse is taken. With one neighbour only (before the first or after the last sample) that one
// is used, grown.
//
// Flags: no_clock (a board has no clock samples: the values are unknown), unsynchronised (a
// neighbouring sample says the clock was not synchronised: no bound), clock_step (a "step" sample of
// unknown size of either board lies between the cause and effect times: the latency straddles a
// clock step; steps of known size are corrected before pairing, clock_steps.hpp; board_record also
// sets it on every pair after a step of unknown offset), gated
// (a sync gate is set and the sample's clock part max_err_cause + max_err_effect exceeds it, or it is
// unsynchronised or straddles a step). With gate_refuse, gated samples stay in the pairs but leave
// the statistics.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/time.hpp"
#include "m2mlat/pairing/pair.hpp"
#include "m2mlat/stats/summary.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::analysis {

struct ScenarioResult;

inline constexpr std::int64_t kUnbounded = std::numeric_limits<std::int64_t>::max();

// The coverage factor of the expanded uncertainty: U95 = k u, about 95 % for a normal error.
inline constexpr double kCoverageFactor = 2;

struct UncertaintyOptions {
  core::Duration kernel_max{0};  // bound on |irq latency effect - irq latency cause|, ns
  // Standard uncertainty of one board's interrupt timestamp, ns (each board's; a measured cyclictest sd).
  core::Duration kernel_u = std::chrono::microseconds{5};
  // Standard uncertainty of the asymmetry of one synchronisation path (a board to its reference), ns.
  core::Duration path_u = std::chrono::microseconds{100};
  core::Duration calibration_max{0};        // bound on the sensors' misalignment, as time, ns
  core::Duration calibration_u{0};          // its standard uncertainty, ns
  double growth_ppm = 15;                   // drift of a clock sample's values with distance, ppm (ns/ms)
  std::optional<core::Duration> sync_gate;  // flag samples whose clock part exceeds this
  bool gate_refuse = false;                 // leave gated samples out of the statistics
};

// Bits of SampleUncertainty::flags. Exported: never renumber.
enum UncertaintyFlag : std::uint32_t {
  kUncertaintyNoClock = 1u << 0,
  kUncertaintyUnsynchronised = 1u << 1,
  kUncertaintyClockStep = 1u << 2,
  kUncertaintyGated = 1u << 3,
};

struct SampleUncertainty {
  std::int64_t max_error_ns = 0;  // the worst-case bound; kUnbounded when a clock was unsynchronised;
                                  // 0 when unknown
  std::int64_t u_ns = 0;          // the standard uncertainty (k = 1); likewise
  std::int64_t sync_max_ns = 0;   // the clock part of max_error (both boards), what the gate tests
  std::uint32_t flags = 0;        // UncertaintyFlag bits
  bool known() const { return (flags & kUncertaintyNoClock) == 0; }
  bool bounded() const { return known() && max_error_ns != kUnbounded; }
  bool gated() const { return (flags & kUncertaintyGated) != 0; }
  bool flagged() const { return (flags & ~kUncertaintyNoClock) != 0; }
  // The expanded uncertainty U95 = k u (kCoverageFactor), ns; kUnbounded when u is.
  std::int64_t expanded_ns() const;
  friend bool operator==(const SampleUncertainty&, const SampleUncertainty&) = default;
};

// One board's clock samples (source other than "step"), by time, and its clock steps.
struct ClockTrack {
  std::vector<store::ClockSample> samples;  // by time
  std::vector<double> skew_ppm;             // per sample: its daemon's rate uncertainty, ppm (detail)
  std::vector<std::int64_t> steps_ns;       // times of "step" samples of unknown size, sorted
  // The same steps as records (store/clock_step.hpp): the size and its uncertainty (size_max_ns,
  // size_est_ns) that a corrected event carries (clock_steps.hpp; per event in ScenarioResult::steps).
  std::vector<store::ClockStep> step_records;
  std::string node;                         // the board (set by the caller; empty: unnamed)
  std::string reference;                    // the node its daemon follows (detail "ref_name" of its last
                                            // sample); empty: its own time servers
  bool empty() const { return samples.empty(); }
};
// From samples in any order; only those on `clock` are kept.
ClockTrack make_clock_track(std::vector<store::ClockSample> samples,
                            core::Clock clock = core::Clock::realtime);

// One board's state at t_ns (rules above). found = false when the track is empty.
struct ClockBound {
  bool found = false;
  bool synchronised = false;
  std::int64_t max_error_ns = 0;  // kUnbounded when not synchronised
  std::int64_t u_ns = 0;          // standard uncertainty of the offset from its reference; likewise
  double skew_ppm = 0;            // the larger of the neighbours' rate uncertainties, ppm
};
ClockBound bound_at(const ClockTrack& track, std::int64_t t_ns, double growth_ppm);
// The neighbouring samples' own offset estimate (offset_ns of the nearer neighbour), if any.
std::optional<std::int64_t> offset_at(const ClockTrack& track, std::int64_t t_ns);
// True if the track has a step at a time in [from_ns, to_ns] (either order).
bool step_between(const ClockTrack& track, std::int64_t from_ns, std::int64_t to_ns);

// bounce_span_ns: the pair's pairing::Pair::bounce_span_ns, added to max_error.
SampleUncertainty pair_uncertainty(const ClockTrack& cause, const ClockTrack& effect, std::int64_t cause_ns,
                                   std::int64_t effect_ns, const UncertaintyOptions& options,
                                   std::int64_t bounce_span_ns = 0);
// One per pair, its edges' times from `times`.
std::vector<SampleUncertainty> pair_uncertainties(const ClockTrack& cause, const ClockTrack& effect,
                                                  std::span<const pairing::Pair> pairs,
                                                  pairing::PairTimes times,
                                                  const UncertaintyOptions& options);

struct UncertaintySummary {
  std::size_t samples = 0;         // pairs
  std::size_t known = 0;           // with both boards' clock state
  std::size_t bounded = 0;         // ... and both synchronised
  std::size_t unsynchronised = 0;  // flag counts
  std::size_t clock_step = 0;
  std::size_t gated = 0;
  std::size_t flagged = 0;                      // any flag but no_clock
  std::size_t refused = 0;                      // gated samples left out of the statistics
  double median_max_ms = stats::Summary::kNaN;  // over the bounded samples
  double p95_max_ms = stats::Summary::kNaN;
  double worst_max_ms = stats::Summary::kNaN;
  double median_u_ms = stats::Summary::kNaN;    // standard uncertainty (k = 1)
  double median_U95_ms = stats::Summary::kNaN;  // expanded uncertainty (k = 2)
  double share_flagged() const {
    return samples == 0 ? stats::Summary::kNaN : static_cast<double>(flagged) / static_cast<double>(samples);
  }
};
UncertaintySummary summarize_uncertainty(std::span<const SampleUncertainty> samples, bool gate_refuse);

// Fills result.uncertainty from the two boards' clock tracks (left empty when both are empty) and,
// when options.gate_refuse left any sample out, recomputes result.summary with `summary_options`.
// The tracks of a store's scenario are loaded by attach_board_record (board_record.hpp).
void attach_uncertainty(ScenarioResult& result, const ClockTrack& cause, const ClockTrack& effect,
                        const UncertaintyOptions& options, const stats::SummaryOptions& summary_options);

}  // namespace m2mlat::analysis
