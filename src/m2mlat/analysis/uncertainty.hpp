// The uncertainty of each latency sample from both boards' clock state at its two event times.
//
// A latency is effect_time - cause_time, each stamped by its own board's CLOCK_REALTIME. Its error
// is (error of the effect board's clock at the effect) - (error of the cause board's clock at the
// cause) + (difference of the two interrupt latencies) + (calibration: where on the wheel each
// sensor fires). The boards' sync daemons report their clock state as clock samples
// (store::ClockSample: max_error_ns, a bound on |clock - reference|, and est_error_ns, an estimate of
// it); this file turns them into a bound and an estimate per sample:
//
//   max_error = max_err_cause(t_cause) + max_err_effect(t_effect) + kernel_max + calibration_max
//   est_error = sqrt(est_cause^2 + est_effect^2 + kernel_est^2 + calibration_est^2)
//
// A board's state at time t comes from its two neighbouring clock samples (the last at or before t
// and the first after it): each neighbour's value is grown by growth_ppm times its distance from t
// (the clock may drift that fast between samples: chrony's maximum error grows the same way), and
// the WORSE of the two is taken. Not interpolated: a daemon's bound can jump at a measurement, and
// taking the worse neighbour keeps the bound honest across the jump. With one neighbour only (before
// the first or after the last sample) that one is used, grown.
//
// What est_error means: a 1-sigma estimate, so [latency - est, latency + est] is expected to hold the
// true latency about 68% of the time and +-2 est about 95%, if the daemons' estimates are themselves
// honest 1-sigma values (chrony reports the root dispersion, the sim its model's sd). max_error is a
// bound: [latency - max, latency + max] holds the true latency always, when the daemons' bounds hold
// and kernel_max bounds the interrupt-latency difference.
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

struct UncertaintyOptions {
  core::Duration kernel_max{0};             // bound on |irq latency effect - irq latency cause|, ns
  core::Duration kernel_est{0};             // its 1-sigma estimate, ns
  core::Duration calibration_max{0};        // bound on the sensors' misalignment, as time, ns
  core::Duration calibration_est{0};        // its 1-sigma estimate, ns
  double growth_ppm = 15;                   // growth of a clock sample's values with distance, ppm (ns/ms)
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
  std::int64_t max_error_ns = 0;  // kUnbounded when a clock was unsynchronised; 0 when unknown
  std::int64_t est_error_ns = 0;  // likewise
  std::int64_t sync_max_ns = 0;   // the clock part of max_error (both boards), what the gate tests
  std::uint32_t flags = 0;        // UncertaintyFlag bits
  bool known() const { return (flags & kUncertaintyNoClock) == 0; }
  bool bounded() const { return known() && max_error_ns != kUnbounded; }
  bool gated() const { return (flags & kUncertaintyGated) != 0; }
  bool flagged() const { return (flags & ~kUncertaintyNoClock) != 0; }
  friend bool operator==(const SampleUncertainty&, const SampleUncertainty&) = default;
};

// One board's clock samples (source other than "step"), by time, and its clock steps.
struct ClockTrack {
  std::vector<store::ClockSample> samples;  // by time
  std::vector<std::int64_t> steps_ns;       // times of "step" samples of unknown size, sorted
  // The same steps as records (store/clock_step.hpp): the size and its uncertainty (size_max_ns,
  // size_est_ns) that a corrected event carries (clock_steps.hpp; per event in ScenarioResult::steps).
  std::vector<store::ClockStep> step_records;
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
  std::int64_t est_error_ns = 0;
};
ClockBound bound_at(const ClockTrack& track, std::int64_t t_ns, double growth_ppm);
// The neighbouring samples' own offset estimate (offset_ns of the nearer neighbour), if any.
std::optional<std::int64_t> offset_at(const ClockTrack& track, std::int64_t t_ns);
// True if the track has a step at a time in [from_ns, to_ns] (either order).
bool step_between(const ClockTrack& track, std::int64_t from_ns, std::int64_t to_ns);

SampleUncertainty pair_uncertainty(const ClockTrack& cause, const ClockTrack& effect, std::int64_t cause_ns,
                                   std::int64_t effect_ns, const UncertaintyOptions& options);
std::vector<SampleUncertainty> pair_uncertainties(const ClockTrack& cause, const ClockTrack& effect,
                                                  std::span<const pairing::Pair> pairs,
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
  double median_est_ms = stats::Summary::kNaN;
  double share_flagged() const {
    return samples == 0 ? stats::Summary::kNaN : static_cast<double>(flagged) / static_cast<double>(samples);
  }
};
UncertaintySummary summarize_uncertainty(std::span<const SampleUncertainty> samples, bool gate_refuse);

// Per-pair columns for the pairs export (formats::PairExportOptions): max_error and est_error, ns;
// nullopt where unknown or unbounded. Pairs past the end of `samples` get nullopt.
struct UncertaintyColumns {
  std::vector<std::optional<std::int64_t>> max_error_ns, est_error_ns;
};
void append_columns(UncertaintyColumns& columns, std::span<const SampleUncertainty> samples,
                    std::size_t pairs);

// Fills result.uncertainty from the two boards' clock tracks (left empty when both are empty) and,
// when options.gate_refuse left any sample out, recomputes result.summary with `summary_options`.
// The tracks of a store's scenario are loaded by attach_board_record (board_record.hpp).
void attach_uncertainty(ScenarioResult& result, const ClockTrack& cause, const ClockTrack& effect,
                        const UncertaintyOptions& options, const stats::SummaryOptions& summary_options);

}  // namespace m2mlat::analysis
