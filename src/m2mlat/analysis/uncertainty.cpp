// Per-sample uncertainty from the boards' clock samples (rules in uncertainty.hpp).
#include "m2mlat/analysis/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

namespace {

constexpr std::string_view kStepSource = "step";
constexpr std::string_view kKernelSource = "adjtimex";

// a + b without overflow: kUnbounded absorbs.
std::int64_t add_saturating(std::int64_t a, std::int64_t b) {
  if (a == kUnbounded || b == kUnbounded || a > kUnbounded - b) return kUnbounded;
  return a + b;
}

std::int64_t distance(std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; }

// growth_ppm * distance, in whole ns, rounded up.
std::int64_t growth(double growth_ppm, std::int64_t distance_ns) {
  const double g = std::ceil(growth_ppm * 1e-6 * static_cast<double>(distance_ns));
  return g >= static_cast<double>(kUnbounded) ? kUnbounded : static_cast<std::int64_t>(g);
}

bool synchronised(const store::ClockSample& s) {
  return s.synchronised && s.max_error_ns != kUnbounded && s.max_error_ns >= 0;
}

double sq(double v) { return v * v; }

// A non-negative double in ns as int64, kUnbounded when too large.
std::int64_t to_ns(double v) {
  return v >= static_cast<double>(kUnbounded) ? kUnbounded : static_cast<std::int64_t>(std::llround(v));
}

// The two members of a sample's detail the model reads (both optional: the detail is what the source
// gave, and a source that gives neither leaves the defaults: no rate term, no reference).
struct Detail {
  double skew_ppm = 0;
  std::string ref_name;
};
Detail detail_of(const store::ClockSample& s) {
  Detail d;
  if (s.detail_json.empty()) return d;
  const auto j = nlohmann::json::parse(s.detail_json, nullptr, false);
  if (!j.is_object()) return d;
  if (const auto it = j.find("skew_ppm"); it != j.end() && it->is_number() && it->get<double>() > 0)
    d.skew_ppm = it->get<double>();
  if (const auto it = j.find("ref_name"); it != j.end() && it->is_string())
    d.ref_name = it->get<std::string>();
  return d;
}

}  // namespace

ClockTrack make_clock_track(std::vector<store::ClockSample> samples, core::Clock clock) {
  ClockTrack track;
  // A daemon's own samples (chrony, ptp, ...) describe its clock; the kernel's adjtimex state is only
  // what the daemon chose to tell the kernel. chronyd serving its own clock (`local stratum`, the
  // reference board of a co-referenced rig) or running without `rtcsync` leaves STA_UNSYNC set while
  // it reports itself synchronised, and those adjtimex samples would mark every pair unsynchronised.
  // So a board's adjtimex samples count only when it has no daemon's samples.
  const bool has_daemon = std::any_of(samples.begin(), samples.end(), [&](const store::ClockSample& s) {
    return s.time.clock() == clock && s.source != kStepSource && s.source != kKernelSource;
  });
  for (auto& s : samples) {
    if (s.time.clock() != clock) continue;
    if (s.source == kStepSource) {
      // A step of known size is taken out of the later stamps before pairing (clock_steps.hpp): only
      // the others leave a latency that straddles them wrong.
      auto step = store::clock_step_of(s);
      if (!step || !step->size_ns) track.steps_ns.push_back(s.time.ns());
      if (step) track.step_records.push_back(std::move(*step));
    } else if (!has_daemon || s.source != kKernelSource)
      track.samples.push_back(std::move(s));
  }
  std::stable_sort(track.samples.begin(), track.samples.end(),
                   [](const auto& a, const auto& b) { return a.time.ns() < b.time.ns(); });
  std::sort(track.steps_ns.begin(), track.steps_ns.end());
  track.skew_ppm.reserve(track.samples.size());
  for (const auto& s : track.samples) {
    auto d = detail_of(s);
    track.skew_ppm.push_back(d.skew_ppm);
    track.reference = std::move(d.ref_name);  // the last sample's: what the daemon follows now
  }
  std::stable_sort(track.step_records.begin(), track.step_records.end(),
                   [](const auto& a, const auto& b) { return a.at_ns < b.at_ns; });
  return track;
}

ClockBound bound_at(const ClockTrack& track, std::int64_t t_ns, double growth_ppm) {
  ClockBound out;
  if (track.samples.empty()) return out;
  out.found = true;
  out.synchronised = true;
  // The first sample after t, and the one before it (the last at or before t).
  const auto next = std::upper_bound(track.samples.begin(), track.samples.end(), t_ns,
                                     [](std::int64_t t, const auto& s) { return t < s.time.ns(); });
  auto consider = [&](std::vector<store::ClockSample>::const_iterator it) {
    const store::ClockSample& s = *it;
    if (!synchronised(s)) {
      out.synchronised = false;
      out.max_error_ns = out.u_ns = kUnbounded;
      return;
    }
    if (!out.synchronised) return;
    const std::int64_t d = distance(s.time.ns(), t_ns);
    out.max_error_ns = std::max(out.max_error_ns, add_saturating(s.max_error_ns, growth(growth_ppm, d)));
    // The drift as a standard uncertainty: a frequency error uniform in +-growth_ppm.
    const double drift = growth_ppm * 1e-6 / std::sqrt(3.0) * static_cast<double>(d);
    const double est = static_cast<double>(std::max<std::int64_t>(s.est_error_ns, 0));
    out.u_ns = std::max(out.u_ns, to_ns(std::sqrt(sq(est) + sq(drift))));
    out.skew_ppm =
        std::max(out.skew_ppm, track.skew_ppm[static_cast<std::size_t>(it - track.samples.begin())]);
  };
  if (next != track.samples.begin()) consider(std::prev(next));
  if (next != track.samples.end()) consider(next);
  return out;
}

std::optional<std::int64_t> offset_at(const ClockTrack& track, std::int64_t t_ns) {
  if (track.samples.empty()) return std::nullopt;
  const auto next = std::upper_bound(track.samples.begin(), track.samples.end(), t_ns,
                                     [](std::int64_t t, const auto& s) { return t < s.time.ns(); });
  if (next == track.samples.begin()) return next->offset_ns;
  const auto prev = std::prev(next);
  if (next == track.samples.end() || distance(prev->time.ns(), t_ns) <= distance(next->time.ns(), t_ns))
    return prev->offset_ns;
  return next->offset_ns;
}

bool step_between(const ClockTrack& track, std::int64_t from_ns, std::int64_t to_ns) {
  if (from_ns > to_ns) std::swap(from_ns, to_ns);
  const auto it = std::lower_bound(track.steps_ns.begin(), track.steps_ns.end(), from_ns);
  return it != track.steps_ns.end() && *it <= to_ns;
}

std::int64_t SampleUncertainty::expanded_ns() const {
  return u_ns == kUnbounded ? kUnbounded : to_ns(kCoverageFactor * static_cast<double>(u_ns));
}

SampleUncertainty pair_uncertainty(const ClockTrack& cause, const ClockTrack& effect, std::int64_t cause_ns,
                                   std::int64_t effect_ns, const UncertaintyOptions& options,
                                   std::int64_t bounce_span_ns) {
  SampleUncertainty u;
  const ClockBound c = bound_at(cause, cause_ns, options.growth_ppm);
  const ClockBound e = bound_at(effect, effect_ns, options.growth_ppm);
  if (step_between(cause, cause_ns, effect_ns) || step_between(effect, cause_ns, effect_ns))
    u.flags |= kUncertaintyClockStep;
  const auto nsd = [](core::Duration d) { return static_cast<double>(d.count()); };
  if (!c.found || !e.found) {
    u.flags |= kUncertaintyNoClock;
  } else if (!cause.node.empty() && cause.node == effect.node) {
    // One board stamped both edges (two channels of one node: single-board glass-to-glass). Its
    // offset from any reference is in both stamps and cancels, synchronised or not; what is left is
    // how far its clock moves during the latency, at most growth_ppm (uniform: / sqrt 3 as u).
    const std::int64_t dt = distance(cause_ns, effect_ns);
    u.sync_max_ns = growth(options.growth_ppm, dt);
    u.max_error_ns = add_saturating(add_saturating(u.sync_max_ns, options.kernel_max.count()),
                                    add_saturating(options.calibration_max.count(), bounce_span_ns));
    const double drift = options.growth_ppm * 1e-6 / std::sqrt(3.0) * static_cast<double>(dt);
    u.u_ns = to_ns(std::sqrt(sq(drift) + 2 * sq(nsd(options.kernel_u)) + sq(nsd(options.calibration_u))));
  } else if (!c.synchronised || !e.synchronised) {
    u.flags |= kUncertaintyUnsynchronised;
    u.max_error_ns = u.u_ns = u.sync_max_ns = kUnbounded;
  } else {
    u.sync_max_ns = add_saturating(c.max_error_ns, e.max_error_ns);
    u.max_error_ns = add_saturating(add_saturating(u.sync_max_ns, options.kernel_max.count()),
                                    add_saturating(options.calibration_max.count(), bounce_span_ns));
    const double path = nsd(options.path_u);
    double clock_sq = 0;
    if (!cause.node.empty() && effect.reference == cause.node) {
      // Co-referenced: the cause clock's error is in both stamps; what is left of it is its motion
      // over the latency, at the rate its daemon reports, at most that of two independent readings.
      const double dt = static_cast<double>(distance(cause_ns, effect_ns));
      const double moved = std::min(c.skew_ppm * 1e-6 * dt, std::sqrt(2.0) * static_cast<double>(c.u_ns));
      clock_sq = sq(static_cast<double>(e.u_ns)) + sq(path) + sq(moved);
    } else {
      clock_sq = sq(static_cast<double>(c.u_ns)) + sq(static_cast<double>(e.u_ns)) + 2 * sq(path);
    }
    u.u_ns = to_ns(std::sqrt(clock_sq + 2 * sq(nsd(options.kernel_u)) + sq(nsd(options.calibration_u))));
  }
  if (options.sync_gate && u.known() &&
      ((u.flags & (kUncertaintyUnsynchronised | kUncertaintyClockStep)) != 0 ||
       u.sync_max_ns > options.sync_gate->count()))
    u.flags |= kUncertaintyGated;
  return u;
}

std::vector<SampleUncertainty> pair_uncertainties(const ClockTrack& cause, const ClockTrack& effect,
                                                  std::span<const pairing::Pair> pairs,
                                                  pairing::PairTimes times,
                                                  const UncertaintyOptions& options) {
  std::vector<SampleUncertainty> out;
  out.reserve(pairs.size());
  for (const auto& p : pairs)
    out.push_back(
        pair_uncertainty(cause, effect, times.cause(p), times.effect(p), options, p.bounce_span_ns));
  return out;
}

UncertaintySummary summarize_uncertainty(std::span<const SampleUncertainty> samples, bool gate_refuse) {
  UncertaintySummary s;
  s.samples = samples.size();
  std::vector<std::int64_t> max, u_values, expanded;
  for (const auto& u : samples) {
    if (u.known()) ++s.known;
    if (u.flags & kUncertaintyUnsynchronised) ++s.unsynchronised;
    if (u.flags & kUncertaintyClockStep) ++s.clock_step;
    if (u.gated()) ++s.gated;
    if (u.flagged()) ++s.flagged;
    if (gate_refuse && u.gated()) ++s.refused;
    if (u.bounded()) {
      ++s.bounded;
      max.push_back(u.max_error_ns);
      u_values.push_back(u.u_ns);
      expanded.push_back(u.expanded_ns());
    }
  }
  if (!max.empty()) {
    s.median_u_ms = stats::median(std::move(u_values)) / 1e6;
    s.median_U95_ms = stats::median(std::move(expanded)) / 1e6;
    std::sort(max.begin(), max.end());
    s.median_max_ms = stats::quantile(std::span<const std::int64_t>(max), 0.5) / 1e6;
    s.p95_max_ms = stats::quantile(std::span<const std::int64_t>(max), 0.95) / 1e6;
    s.worst_max_ms = static_cast<double>(max.back()) / 1e6;
  }
  return s;
}

void attach_uncertainty(ScenarioResult& result, const ClockTrack& cause, const ClockTrack& effect,
                        const UncertaintyOptions& options, const stats::SummaryOptions& summary_options) {
  result.uncertainty.clear();
  result.refuse_gated = false;
  if (cause.empty() && effect.empty()) return;
  result.uncertainty = pair_uncertainties(cause, effect, result.match.pairs, result.times(), options);
  // An event corrected by a clock step of known size carries the size's uncertainty (clock_steps.hpp):
  // its bound adds to the worst case, its standard uncertainty to u in quadrature.
  const auto add_step = [](SampleUncertainty& u, const SideSteps& side, std::int64_t event) {
    const auto k = static_cast<std::size_t>(event);
    if (!u.bounded() || side.at(k) != StepMark::corrected) return;
    const auto bound = side.bound(k);
    u.max_error_ns = add_saturating(u.max_error_ns, bound.max_ns);
    u.u_ns = to_ns(std::hypot(static_cast<double>(u.u_ns), static_cast<double>(bound.est_ns)));
  };
  for (std::size_t i = 0; i < result.uncertainty.size(); ++i) {
    add_step(result.uncertainty[i], result.steps.cause, result.match.pairs[i].cause_index);
    add_step(result.uncertainty[i], result.steps.effect, result.match.pairs[i].effect_index);
  }
  if (!options.gate_refuse) return;
  result.refuse_gated = true;
  if (std::any_of(result.uncertainty.begin(), result.uncertainty.end(),
                  [](const auto& u) { return u.gated(); }))
    summarize(result, summary_options);
}

}  // namespace m2mlat::analysis
