// The two boards' clocks: what each node's CLOCK_REALTIME reads at a given true time.
//
// Each clock has an oscillator with a frequency error (drift, ppm) that wanders as a random walk,
// and is disciplined by a synchronisation daemon that measures its offset to a reference once per
// poll interval and slews the clock towards it (a proportional-integral loop, as chrony and ntpd
// do). The measurement is noisy, occasionally an outlier (a delayed sync packet), and biased by the
// path's asymmetry, which no daemon can see. Between polls a clock runs at a constant rate, so its
// error is piecewise linear in true time and the reading never goes backwards.
//
// Modes: co_referenced - the operator board follows its own time servers and serves the vehicle
// board, whose clock follows the operator's; autonomous - each board follows its own servers;
// perfect - both clocks read true time; free - no synchronisation, each clock drifts from its
// initial offset.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/sim/random.hpp"

namespace m2mlat::sim {

// Names are used in overrides and docs: keep them stable.
enum class SyncMode : std::uint8_t { perfect = 0, co_referenced = 1, autonomous = 2, free = 3 };
std::string_view to_string(SyncMode mode);
SyncMode parse_sync_mode(std::string_view text);  // throws core::Error(usage) listing the modes

// One board's clock.
struct ClockConfig {
  core::Duration initial_offset{0};  // free mode: reading - true time at the start (synchronised
                                     // modes start converged, at sync_bias)
  double drift_ppm = 0;              // oscillator frequency error, ppm (1 ppm = 1 us/s)
  double wander_ppm_per_sqrt_s = 0;  // random walk of the frequency error: its std dev after 1 s, ppm
  core::Duration sync_bias{0};       // the error synchronisation leaves on average relative to the
                                     // reference (path asymmetry); |bias| <= rtt/2 physically
  // A step of CLOCK_REALTIME (settimeofday, chrony's makestep to another reference): at true time
  // start + step_at the reading jumps by `step` (positive = forward) and stays there: the daemon's
  // reference moved with it, so it does not slew it back (0 = no step; every mode, perfect included).
  core::Duration step_at{0};  // after the run's start
  core::Duration step{0};     // new reading - old reading

  friend bool operator==(const ClockConfig&, const ClockConfig&) = default;
};

// A synchronisation path from a node to its reference.
struct SyncLink {
  core::Duration noise{0};         // std dev of one offset measurement
  core::Duration rtt{0};           // round-trip delay; the daemon's error bound contains rtt/2
  double outlier_probability = 0;  // chance that a measurement is an outlier (a delayed packet)
  core::Duration outlier_mean{0};  // mean size of an outlier (exponential); a positive value makes
                                   // the daemon slew the clock ahead, a negative one behind

  friend bool operator==(const SyncLink&, const SyncLink&) = default;
};

struct SyncConfig {
  SyncMode mode = SyncMode::co_referenced;
  core::Duration poll_interval = std::chrono::seconds(1);  // one measurement and correction per
                                                           // interval; also the model's time step
  SyncLink upstream;  // a board to its own time servers: the operator in co_referenced, both in autonomous
  SyncLink peer;      // the vehicle board to the operator board (co_referenced)
  double loop_gain = 0.3;        // fraction of a measured offset slewed away in the next interval
  double frequency_gain = 0.02;  // fraction of a measured offset added to the frequency correction
  // The fastest the daemon adjusts the clock's rate (its frequency and offset corrections together),
  // ppm: chrony's `maxslewrate`, which m2mlat's chrony.conf sets to 500 so that the kernel log's own
  // stamps tell a step from a slew (analysis/kernel_log_steps.hpp).
  double max_slew_ppm = 500;

  friend bool operator==(const SyncConfig&, const SyncConfig&) = default;
};

struct SyncInfo {
  std::string_view name;
  std::string_view description;  // one line
};
std::span<const SyncInfo> sync_profiles();
// The named synchronisation set-up (mode, links, loop); throws core::Error(usage) for unknown names.
SyncConfig sync_profile(std::string_view name);

void validate(const ClockConfig& clock, std::string_view field);
void validate(const SyncConfig& sync, std::string_view field);

// What the model knows about one clock at one moment.
struct ClockState {
  double error_ns = 0;                 // reading - true time (unrounded)
  core::Duration estimated_offset{0};  // the daemon's last measured offset to its reference
  core::Duration error_bound{0};       // the daemon's bound on |error|: root delay / 2 + root
                                       // dispersion; Duration::max() when not synchronised (free)
  // What the daemon reports of its own scatter, from the measured offsets it has seen (not from the
  // error it cannot see): the standard uncertainty (k = 1) of the clock's offset from its reference,
  // sqrt(g / (2 - g)) x the RMS of the measured offsets (a proportional loop of gain g leaves that
  // much of a measurement noise on the clock: the kind of estimate a daemon gives the kernel as
  // adjtimex's esterror),
  // and the sd of the rate at which it slews the clock, g x RMS / poll interval (ppm; chrony's skew).
  core::Duration error_estimate{0};  // 0 when not disciplined
  core::Duration rms_offset{0};      // RMS of the measured offsets (chrony's "RMS offset")
  double skew_ppm = 0;
};

// Both nodes' clocks, stepped together on the poll grid (the vehicle's reference in co_referenced
// mode is the operator's clock). The model only moves forward: a query may not go back before the
// poll interval that holds the latest query.
class ClockPair {
 public:
  // `start_ns`: true time (ns since the epoch) where the model starts; `seed`: the run's seed.
  ClockPair(const ClockConfig& cause, const ClockConfig& effect, const SyncConfig& sync,
            std::int64_t start_ns, std::uint64_t seed);

  // The state of `role`'s clock (cause or effect) at true time `true_ns`. Throws
  // core::Error(internal) if `true_ns` lies before the current poll interval.
  ClockState at(core::Role role, std::int64_t true_ns);
  // Reading - true time at `true_ns`, rounded to whole nanoseconds (same rules as at()).
  core::Duration error(core::Role role, std::int64_t true_ns);

 private:
  struct Node {
    ClockConfig config;
    bool disciplined = false;  // false: free running (or perfect)
    SyncLink link;             // the path to its reference, when disciplined
    Rng rng;
    double error_ns = 0;        // reading - true time at grid_ns_
    double rate = 0;            // d(error)/dt until the next grid point (dimensionless)
    double oscillator = 0;      // oscillator frequency error (dimensionless)
    double correction = 0;      // the daemon's frequency correction (dimensionless)
    double measured_ns = 0;     // last measured offset
    double dispersion_var = 0;  // running mean of measured_ns^2 (the daemon's jitter estimate)
    double error_var = 0;       // running mean of the clock error's variance its corrections imply, ns^2
    double applied_var = 0;     // running mean of the squared offset correction a poll, ns^2
    std::int64_t step_true_ns = 0;  // true time of the configured step (config.step != 0)
    bool stepped = false;           // the step is in error_ns already
    Node(const ClockConfig& c, std::uint64_t seed, std::uint64_t stream) : config(c), rng(seed, stream) {}
  };
  void step();
  double step_part(const Node& node, std::int64_t true_ns) const;  // the step not yet in error_ns
  void discipline(Node& node, double reference_error_ns);
  ClockState state_of(const Node& node, std::int64_t true_ns) const;

  SyncConfig sync_;
  Node cause_, effect_;
  std::int64_t grid_ns_;  // true time of the last grid point
  double wander_scale_;   // sqrt(poll interval in s) * 1e-6: turns ppm/sqrt(s) into a per-step change
  double loop_factor_;    // var(clock error) / var(offset correction) of the unlimited loop
};

}  // namespace m2mlat::sim
