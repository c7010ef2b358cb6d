// Options shared by the subcommands that pair and summarise (pair, stats, export, demo): the
// matcher's window, the statistics' thresholds and bootstrap, and which channels are cause and
// effect. Registered on a CLI11 subcommand, turned into library options after parsing
// (analysis::PipelineOptions for the offline pipeline).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"

namespace m2mlat::cli {

struct MatchFlags {
  std::string min_latency = "0ms";
  std::string max_latency = "10s";
  std::string refractory = "10ms";
  std::string tolerance = "none";
  std::string burst_gap = "auto";
  std::vector<double> magnets;  // the wheels' magnet layout, degrees (empty: one magnet)
  bool include_ambiguous = false;  // statistics over ambiguous pairs too
  std::string matcher = "rules";    // rules or model (docs/matcher.md)
  double min_probability = 0.99;    // --matcher model: pairs below it are flagged
  void add_to(CLI::App& sub);
  pairing::MatchOptions options() const;  // throws core::Error(usage) naming the flag
};

struct StatsFlags {
  std::vector<std::string> thresholds{"170ms", "300ms", "400ms", "1s"};
  std::vector<double> percentiles;
  // Resamples kept in memory: 8 bytes per resample and quantile. At 10^6 the resampling error of
  // an interval's ends (~1/sqrt(B)) is far below its width; the bound keeps a typo from asking for
  // terabytes.
  static constexpr std::size_t kMaxBootstrap = 1'000'000;
  std::size_t bootstrap = 2000;  // resamples; 0 = no confidence intervals
  std::uint64_t seed = 1;
  double level = 0.95;
  // Per-sample uncertainty from the boards' clock samples (analysis/uncertainty.hpp).
  std::string sync_gate;             // flag samples whose clock bound exceeds this; empty = no gate
  bool sync_gate_refuse = false;     // and leave them out of the statistics
  std::string kernel_error = "0us";  // bound on the two boards' timestamping asymmetry
  std::string kernel_u = "5us";      // standard uncertainty of one board's interrupt timestamp
  std::string path_u = "100us";      // standard uncertainty of one synchronisation path's asymmetry
  std::string calibration_error = "0us";  // bound on the sensors' misalignment, as time
  std::string calibration_u = "0us";      // its standard uncertainty
  // The same from the Hall sensors' geometry: a misalignment (degrees) at a steering rate (deg/s).
  double misalignment_deg = 0;
  double rate_deg_s = 0;
  void add_to(CLI::App& sub);
  stats::SummaryOptions options() const;
  analysis::UncertaintyOptions uncertainty_options() const;  // throws core::Error(usage) naming the flag
};

struct SelectionFlags {
  std::string cause, effect;  // node[/channel]; empty = by session role
  std::string edge = "falling";
  std::string min_pulse = "auto";  // interference filter (pairing/glitch_filter.hpp): auto, off or a duration
  void add_to(CLI::App& sub);
  analysis::Selection selection() const;
};

// The full loop from stores (analysis/store_chains.hpp): scenarios with gyroscope traces are chained
// (station onset -> vehicle onset -> LED -> photo edge) instead of paired as events. --cause and
// --effect name the station and the vehicle, --edge the photo edges.
struct ChainFlags {
  std::string detector = "flank";  // onset detector (onset/detectors.hpp)
  std::string led_channel = "led", photo_channel = "photo";
  std::string led_bound = "100us";  // an LED write's half-width where its session recorded none
  bool no_chains = false;           // pair traced scenarios' events like any others
  void add_to(CLI::App& sub);
  // Takes the traced scenarios out of `inputs` and chains them (warnings on stderr); none with
  // --no-chains. Throws core::Error(usage) naming a bad flag.
  std::vector<analysis::FullLoopResult> take(analysis::PipelineInputs& inputs,
                                             const SelectionFlags& selection, const StatsFlags& stats) const;
};

// The pipeline's options from the three groups of flags, converted in this order (the first bad flag
// is the one reported): selection, pairing, statistics, uncertainty.
analysis::PipelineOptions pipeline_options(const SelectionFlags& selection, const MatchFlags& match,
                                           const StatsFlags& stats);

}  // namespace m2mlat::cli
