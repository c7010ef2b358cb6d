// Registration and conversion of the shared pairing/statistics/selection flags.
#include "m2mlat/cli/analysis_options.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/analysis/store_chains.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/selftest/budget.hpp"

namespace m2mlat::cli {

void MatchFlags::add_to(CLI::App& sub) {
  auto* group = sub.add_option_group("pairing");
  group->add_option("--min-latency", min_latency, "Smallest plausible latency (e.g. 0ms)")
      ->capture_default_str();
  group->add_option("--max-latency", max_latency, "Largest plausible latency: the pairing window")
      ->capture_default_str();
  group->add_option("--refractory", refractory, "Edges closer than this after a kept edge are bounces")
      ->capture_default_str();
  group->add_option("--tolerance", tolerance,
                    "Largest deviation of a pair from the local typical latency (none: the data decide)")
      ->capture_default_str();
  group->add_option("--burst-gap", burst_gap,
                    "Edges closer than this form one burst (auto: from --magnets, 250ms for one magnet)")
      ->capture_default_str();
  group->add_option("--magnets", magnets, "Magnet angles on the wheels in degrees, e.g. 0,90,180,270")
      ->delimiter(',');
  group->add_option("--matcher", matcher,
                    "rules, or model: the alignment model fitted to the log, a probability for every pair")
      ->check(CLI::IsMember({"rules", "model"}))
      ->capture_default_str();
  group->add_option("--min-probability", min_probability,
                    "With --matcher model: pairs less probable than this are flagged and left out")
      ->check(CLI::Range(0.5, 0.999999))
      ->capture_default_str();
  group->add_flag("--include-ambiguous", include_ambiguous,
                  "Include pairs of bursts with a missed or extra edge in the statistics");
}

pairing::MatchOptions MatchFlags::options() const {
  pairing::MatchOptions o;
  // The matcher refuses a window beyond its limit too; here the message names the flag.
  const auto latency = [](const char* flag, const std::string& text) {
    const auto d = duration_flag(flag, text);
    if (d > pairing::kMaxLatency || d < -pairing::kMaxLatency)
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{} {}: a latency is at most {} either way (docs/matcher.md)", flag, text,
                                    core::format_duration(pairing::kMaxLatency)));
    return d;
  };
  o.min_latency = latency("--min-latency", min_latency);
  o.max_latency = latency("--max-latency", max_latency);
  o.refractory = duration_flag("--refractory", refractory);
  o.tolerance = tolerance == "none" ? core::Duration{0} : duration_flag("--tolerance", tolerance);
  o.burst_gap = burst_gap == "auto" ? core::Duration{0} : duration_flag("--burst-gap", burst_gap);
  for (const double angle : magnets)
    if (!(angle >= 0 && angle < 360))
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("--magnets: {} is not an angle in [0, 360) degrees", angle));
  o.magnets_deg = magnets;
  o.method = matcher == "model" ? pairing::MatchOptions::Method::model : pairing::MatchOptions::Method::rules;
  o.min_probability = min_probability;
  return o;
}

void StatsFlags::add_to(CLI::App& sub) {
  auto* group = sub.add_option_group("statistics");
  group->add_option("--threshold", thresholds, "Report the share of latencies above each (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  group->add_option("--percentile", percentiles, "Extra percentiles to report, e.g. 99.9")->delimiter(',');
  group->add_option("--bootstrap", bootstrap, "Bootstrap resamples for the CIs of median and IQR (0: none)")
      ->check(CLI::Range(std::size_t{0}, kMaxBootstrap))
      ->capture_default_str();
  group->add_option("--seed", seed, "Seed of the bootstrap (same seed, same intervals)")
      ->capture_default_str();
  group->add_option("--level", level, "Confidence level of the intervals")->capture_default_str();
  group->add_option("--sync-gate", sync_gate,
                    "Flag latency samples whose clock error bound (both boards) exceeds this, e.g. 5ms");
  group->add_flag("--sync-gate-refuse", sync_gate_refuse,
                  "Leave the samples flagged by --sync-gate out of the statistics");
  group
      ->add_option("--kernel-error", kernel_error,
                   "Bound on the two boards' timestamping asymmetry, added to each sample's max error")
      ->capture_default_str();
  group
      ->add_option("--kernel-u", kernel_u,
                   "Standard uncertainty of one board's interrupt timestamp (e.g. its cyclictest sd), in u")
      ->capture_default_str();
  group
      ->add_option("--path-u", path_u,
                   "Standard uncertainty of the asymmetry of one synchronisation path (a board to its "
                   "reference), in u")
      ->capture_default_str();
  group
      ->add_option("--calibration-error", calibration_error,
                   "Bound on the two sensors' misalignment as time (angle / rate), added to max error")
      ->capture_default_str();
  group->add_option("--calibration-u", calibration_u, "Standard uncertainty of that misalignment, in u")
      ->capture_default_str();
  group->add_option("--misalignment", misalignment_deg,
                    "The sensors' misalignment between the wheels, degrees (with --rate): the calibration "
                    "term as `m2mlat budget` makes it, bound angle / rate, u = bound / sqrt(3)");
  group->add_option("--rate", rate_deg_s, "The steering rate the misalignment is taken at, deg/s");
}

namespace {
// A term of the uncertainty model: a size, so never negative (a negative bound or standard
// uncertainty has no meaning, and squared it would pass unnoticed).
core::Duration uncertainty_term(const std::string& flag, const std::string& text) {
  const auto d = duration_flag(flag, text);
  if (d.count() < 0)
    throw core::Error(core::ErrorKind::usage, fmt::format("{}: '{}' is negative; give a size", flag, text));
  return d;
}
}  // namespace

analysis::UncertaintyOptions StatsFlags::uncertainty_options() const {
  analysis::UncertaintyOptions o;
  if (!sync_gate.empty()) o.sync_gate = duration_flag("--sync-gate", sync_gate);
  if (sync_gate_refuse && sync_gate.empty())
    throw core::Error(core::ErrorKind::usage, "--sync-gate-refuse needs --sync-gate");
  o.gate_refuse = sync_gate_refuse;
  o.kernel_max = uncertainty_term("--kernel-error", kernel_error);
  o.kernel_u = uncertainty_term("--kernel-u", kernel_u);
  o.path_u = uncertainty_term("--path-u", path_u);
  o.calibration_max = uncertainty_term("--calibration-error", calibration_error);
  o.calibration_u = uncertainty_term("--calibration-u", calibration_u);
  if (misalignment_deg != 0 || rate_deg_s != 0) {
    if (o.calibration_max.count() != 0 || o.calibration_u.count() != 0)
      throw core::Error(core::ErrorKind::usage,
                        "--misalignment and --rate make the calibration term: not with --calibration-error or "
                        "--calibration-u");
    if (!(rate_deg_s > 0))
      throw core::Error(core::ErrorKind::usage, "--misalignment needs --rate, the steering rate in deg/s (> 0)");
    const auto term = selftest::calibration_term(misalignment_deg, rate_deg_s, "");
    o.calibration_max = core::Duration{term.value_ns};
    o.calibration_u = core::Duration{std::llround(term.u_ns)};
  }
  return o;
}

stats::SummaryOptions StatsFlags::options() const {
  stats::SummaryOptions o;
  o.thresholds.clear();
  for (const auto& t : thresholds) o.thresholds.push_back(duration_flag("--threshold", t));
  o.extra_percentiles = percentiles;
  if (bootstrap > 0) o.bootstrap = stats::BootstrapOptions{bootstrap, seed, level};
  return o;
}

void SelectionFlags::add_to(CLI::App& sub) {
  auto* group = sub.add_option_group("channels");
  group->add_option("--cause", cause, "Cause channel as node[/channel] (default: the cause sessions' node)");
  group->add_option("--effect", effect,
                    "Effect channel as node[/channel] (default: the effect sessions' node)");
  group->add_option("--edge", edge, "Edges to pair: falling, rising or both")->capture_default_str();
  group
      ->add_option("--min-pulse", min_pulse,
                   "Drop edges that start no pulse this long, e.g. 1ms: interference (needs both edges "
                   "recorded); auto: 1ms where both lines hold both edges; off: none")
      ->capture_default_str();
}

analysis::Selection SelectionFlags::selection() const {
  analysis::Selection s;
  // An empty channel part means "the node's only channel".
  if (!cause.empty()) s.cause = core::parse_channel_ref(cause, "");
  if (!effect.empty()) s.effect = core::parse_channel_ref(effect, "");
  if (edge == "both")
    s.edge.reset();
  else
    s.edge = core::parse_edge(edge);
  s.auto_min_pulse = min_pulse == "auto";
  if (min_pulse != "off" && min_pulse != "auto") {
    s.min_pulse = duration_flag("--min-pulse", min_pulse);
    if (s.min_pulse.count() <= 0)
      throw core::Error(core::ErrorKind::usage, "--min-pulse: a duration above 0, or off");
  }
  return s;
}

analysis::PipelineOptions pipeline_options(const SelectionFlags& selection, const MatchFlags& match,
                                           const StatsFlags& stats) {
  analysis::PipelineOptions o;
  o.selection = selection.selection();
  o.match = match.options();
  o.include_ambiguous = match.include_ambiguous;
  o.summary = stats.options();
  o.uncertainty = stats.uncertainty_options();
  return o;
}

void ChainFlags::add_to(CLI::App& sub) {
  auto* group = sub.add_option_group("full loop (stores with gyroscope traces)");
  group->add_option("--detector", detector, "Onset detector of the gyroscope traces: flank or reference")
      ->capture_default_str();
  group->add_option("--led-channel", led_channel, "The vehicle's LED writes (m2mlat led --channel)")
      ->capture_default_str();
  group->add_option("--photo-channel", photo_channel, "The station's phototransistor edges (see --edge)")
      ->capture_default_str();
  group
      ->add_option("--led-bound", led_bound,
                   "An LED write's half-width where its session recorded none (a warning says so)")
      ->capture_default_str();
  group->add_flag("--no-chains", no_chains,
                  "Pair the events of scenarios with gyroscope traces like any others");
}

std::vector<analysis::FullLoopResult> ChainFlags::take(analysis::PipelineInputs& inputs,
                                                       const SelectionFlags& selection,
                                                       const StatsFlags& stats) const {
  if (no_chains) return {};
  static_cast<void>(onset::detector(detector));  // an unknown name is a usage error before any store is read
  const auto chosen = selection.selection();
  analysis::ChainSelection s;
  s.station = chosen.cause;
  s.vehicle = chosen.effect;
  s.led_channel = led_channel;
  s.photo_channel = photo_channel;
  s.photo_edge = chosen.edge;
  s.default_led_bound = duration_flag("--led-bound", led_bound);
  if (s.default_led_bound.count() < 0)
    throw core::Error(core::ErrorKind::usage, "--led-bound: must not be negative");
  analysis::ChainOptions options;
  options.detector = detector;
  options.uncertainty = stats.uncertainty_options();
  std::vector<std::string> warnings;
  auto out = analysis::take_chain_stores(inputs, s, options, stats.options(), warnings);
  for (const auto& w : warnings) warn(w);
  return out;
}

}  // namespace m2mlat::cli
