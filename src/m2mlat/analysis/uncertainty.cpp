// Per-sample uncertainty from the boards' clock samples (rules in uncertainty.hpp).
#include "m2mlat/analysis/uncertainty.hpp"

#include <algorithm>
#include <cmath>

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
    }
    else if (!has_daemon || s.source != kKernelSource)
      track.samples.push_back(std::move(s));
  }
  std::stable_sort(track.samples.begin(), track.samples.end(),
                   [](const auto& a, const auto& b) { return a.time.ns() < b.time.ns(); });
  std::sort(track.steps_ns.begin(), track.steps_ns.end());
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
  auto consider = [&](const store::ClockSample& s) {
    if (!synchronised(s)) {
      out.synchronised = false;
      out.max_error_ns = out.est_error_ns = kUnbounded;
      return;
    }
    if (!out.synchronised) return;
    const std::int64_t grow = growth(growth_ppm, distance(s.time.ns(), t_ns));
    out.max_error_ns = std::max(out.max_error_ns, add_saturating(s.max_error_ns, grow));
    out.est_error_ns =
        std::max(out.est_error_ns, add_saturating(std::max<std::int64_t>(s.est_error_ns, 0), grow));
  };
  if (next != track.samples.begin()) consider(*std::prev(next));
  if (next != track.samples.end()) consider(*next);
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

SampleUncertainty pair_uncertainty(const ClockTrack& cause, const ClockTrack& effect, std::int64_t cause_ns,
                                   std::int64_t effect_ns, const UncertaintyOptions& options) {
  SampleUncertainty u;
  const ClockBound c = bound_at(cause, cause_ns, options.growth_ppm);
  const ClockBound e = bound_at(effect, effect_ns, options.growth_ppm);
  if (step_between(cause, cause_ns, effect_ns) || step_between(effect, cause_ns, effect_ns))
    u.flags |= kUncertaintyClockStep;
  if (!c.found || !e.found) {
    u.flags |= kUncertaintyNoClock;
  } else if (!c.synchronised || !e.synchronised) {
    u.flags |= kUncertaintyUnsynchronised;
    u.max_error_ns = u.est_error_ns = u.sync_max_ns = kUnbounded;
  } else {
    u.sync_max_ns = add_saturating(c.max_error_ns, e.max_error_ns);
    u.max_error_ns = add_saturating(add_saturating(u.sync_max_ns, options.kernel_max.count()),
                                    options.calibration_max.count());
    const auto sq = [](std::int64_t v) { return static_cast<double>(v) * static_cast<double>(v); };
    const double est = std::sqrt(sq(c.est_error_ns) + sq(e.est_error_ns) + sq(options.kernel_est.count()) +
                                 sq(options.calibration_est.count()));
    u.est_error_ns = est >= static_cast<double>(kUnbounded) ? kUnbounded : std::llround(est);
  }
  if (options.sync_gate && u.known() &&
      ((u.flags & (kUncertaintyUnsynchronised | kUncertaintyClockStep)) != 0 ||
       u.sync_max_ns > options.sync_gate->count()))
    u.flags |= kUncertaintyGated;
  return u;
}

std::vector<SampleUncertainty> pair_uncertainties(const ClockTrack& cause, const ClockTrack& effect,
                                                  std::span<const pairing::Pair> pairs,
                                                  const UncertaintyOptions& options) {
  std::vector<SampleUncertainty> out;
  out.reserve(pairs.size());
  for (const auto& p : pairs)
    out.push_back(pair_uncertainty(cause, effect, p.cause_time.ns(), p.effect_time.ns(), options));
  return out;
}

UncertaintySummary summarize_uncertainty(std::span<const SampleUncertainty> samples, bool gate_refuse) {
  UncertaintySummary s;
  s.samples = samples.size();
  std::vector<std::int64_t> max, est;
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
      est.push_back(u.est_error_ns);
    }
  }
  if (!max.empty()) {
    s.median_est_ms = stats::median(std::move(est)) / 1e6;
    std::sort(max.begin(), max.end());
    s.median_max_ms = stats::quantile(std::span<const std::int64_t>(max), 0.5) / 1e6;
    s.p95_max_ms = stats::quantile(std::span<const std::int64_t>(max), 0.95) / 1e6;
    s.worst_max_ms = static_cast<double>(max.back()) / 1e6;
  }
  return s;
}

void append_columns(UncertaintyColumns& columns, std::span<const SampleUncertainty> samples,
                    std::size_t pairs) {
  for (std::size_t i = 0; i < pairs; ++i) {
    const bool bounded = i < samples.size() && samples[i].bounded();
    columns.max_error_ns.push_back(bounded ? std::optional(samples[i].max_error_ns) : std::nullopt);
    columns.est_error_ns.push_back(bounded ? std::optional(samples[i].est_error_ns) : std::nullopt);
  }
}

void attach_uncertainty(ScenarioResult& result, const ClockTrack& cause, const ClockTrack& effect,
                        const UncertaintyOptions& options, const stats::SummaryOptions& summary_options) {
  result.uncertainty.clear();
  result.refuse_gated = false;
  if (cause.empty() && effect.empty()) return;
  result.uncertainty = pair_uncertainties(cause, effect, result.match.pairs, options);
  if (!options.gate_refuse) return;
  result.refuse_gated = true;
  if (std::any_of(result.uncertainty.begin(), result.uncertainty.end(),
                  [](const auto& u) { return u.gated(); }))
    summarize(result, summary_options);
}

}  // namespace m2mlat::analysis
