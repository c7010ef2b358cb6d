// Correcting and marking one board's events after its clock steps (rule in clock_steps.hpp).
#include "m2mlat/analysis/clock_steps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::analysis {

namespace {

constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

// The first synchronised non-step sample at or after t_ns (kNever if none).
std::int64_t good_again(std::span<const store::ClockSample> samples, std::int64_t t_ns) {
  std::int64_t best = kNever;
  for (const auto& s : samples)
    if (s.source != store::kStepSource && s.synchronised && s.time.ns() >= t_ns) best = std::min(best, s.time.ns());
  return best;
}

// Gives a vector's memory back now (assigning {} would keep its capacity).
template <typename Vector>
void free_vector(Vector& v) {
  Vector().swap(v);
}

std::int64_t add_bound(std::int64_t a, std::int64_t b) {
  return a > std::numeric_limits<std::int64_t>::max() - b ? std::numeric_limits<std::int64_t>::max() : a + b;
}

}  // namespace

void leave_out_unknown_clock(ScenarioInput& input,
                             const std::map<std::string, std::vector<store::UnknownClock>>& unknown) {
  const auto side = [&](store::Timestamps& t, const std::string& node, UnknownClockCounts& counts) {
    const auto it = unknown.find(node);
    if (it == unknown.end() || t.t_ns.empty()) return;
    std::vector<bool> out(t.t_ns.size(), false);
    for (const auto& lines : it->second) {
      const auto lo = std::lower_bound(t.t_ns.begin(), t.t_ns.end(), lines.from_ns);
      const auto hi = std::upper_bound(lo, t.t_ns.end(), lines.to_ns);
      for (auto k = lo; k != hi; ++k) {
        auto&& left = out[static_cast<std::size_t>(k - t.t_ns.begin())];
        if (left) continue;
        left = true;
        ++(lines.reason == "before_sync" ? counts.before_sync : counts.outlier);
      }
    }
    if (counts.total() == 0) return;
    if (t.seq.empty()) {  // ids were positions: keep them as they were
      t.seq.resize(t.t_ns.size());
      std::iota(t.seq.begin(), t.seq.end(), std::int64_t{0});
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < t.t_ns.size(); ++k)
      if (!out[k]) t.t_ns[kept] = t.t_ns[k], t.seq[kept] = t.seq[k], ++kept;
    t.t_ns.resize(kept), t.seq.resize(kept);
  };
  side(input.cause, input.cause_ref.node, input.cause_unknown_clock);
  side(input.effect, input.effect_ref.node, input.effect_unknown_clock);
}

std::uint32_t pair_flags(StepMark mark) {
  switch (mark) {
    case StepMark::corrected: return pairing::kPairStepCorrected;
    case StepMark::unknown: return pairing::kPairAfterClockStep;
    case StepMark::none: break;
  }
  return 0;
}

std::vector<store::ClockStep> steps_of(std::span<const store::ClockSample> samples, core::Clock clock) {
  std::vector<store::ClockStep> out;
  for (const auto& s : samples)
    if (s.time.clock() == clock)
      if (auto step = store::clock_step_of(s)) out.push_back(std::move(*step));
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.at_ns < b.at_ns; });
  return out;
}

SideSteps correct_side(store::Timestamps& side, std::span<const store::ClockStep> steps,
                       std::span<const store::ClockSample> samples) {
  SideSteps out;
  out.steps = steps.size();
  const std::size_t n = side.t_ns.size();
  if (steps.empty() || n == 0) return out;
  // Recording order: by store sequence number or file position (a side without seq column is in it).
  // The events are nearly always in it already (a file's, a store's read by seq): then no permutation
  // is built (at 10^7 events each array here is 80 MB).
  std::vector<std::size_t> order;
  if (!std::is_sorted(side.seq.begin(), side.seq.end())) {
    order.resize(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return side.seq[a] < side.seq[b]; });
  }
  const auto index = [&](std::size_t k) { return order.empty() ? k : order[k]; };  // of recording position k
  const auto t = [&](std::size_t k) { return side.t_ns[index(k)]; };  // k-th recorded stamp (raw)
  const auto seq = [&](std::size_t k) {  // its id
    return side.seq.empty() ? static_cast<std::int64_t>(k) : side.seq[index(k)];
  };

  // What each step does, worked out without touching every later event once per step (that made
  // this O(steps x events): 80 % of `m2mlat stats` on a kernel log of 10^7 lines). A step acts on
  // every event recorded from its boundary on, and boundaries never move back from one step to the
  // next, so the steps acting on the event at recording position k are the first applied(k) steps,
  // except where k is one of the step's exceptions (an event stamped where old and new readings
  // overlap, or before the clock is good again: marked unknown, not corrected). The corrections of
  // an event without exceptions are then running totals over the steps, taken in step order as
  // before, so every figure is the one the per-event loop gave.
  // suffix_min[k] = the smallest stamp recorded at or after position k (non-decreasing in k): where
  // the last stamp below a time lies, and where no later stamp can be below it.
  std::vector<std::int64_t> suffix_min(n);
  for (std::size_t k = n; k-- > 0;) suffix_min[k] = k + 1 < n ? std::min(t(k), suffix_min[k + 1]) : t(k);
  std::vector<std::size_t> boundaries;
  boundaries.reserve(steps.size());
  std::vector<std::pair<std::size_t, std::size_t>> exceptions;  // (recording position, step)
  std::size_t from = 0;  // events before this recording position are before every later step
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const auto& step = steps[s];
    // The first recorded event at or after the step's window, from which every event is a candidate:
    // one past the last recorded stamp before it (at or after `from`).
    const auto below = std::partition_point(suffix_min.begin(), suffix_min.end(),
                                            [&](std::int64_t m) { return m < step.earliest_ns; });
    const auto last_before = static_cast<std::size_t>(below - suffix_min.begin());  // positions < it
    std::size_t start = std::max(from, last_before);
    std::size_t boundary = start;  // first recorded event after the step
    std::int64_t ambiguous_below = step.earliest_ns;  // stamps in [earliest, this) may lie on either side
    if (step.size_ns) {
      ambiguous_below = step.at_ns - *step.size_ns;
      if (*step.size_ns < 0) {
        // A step back shows in the recording order as a stamp lower than the one before it.
        for (std::size_t k = start + 1; k < n; ++k)
          if (t(k) < t(k - 1) && t(k) >= step.earliest_ns) {
            boundary = k;
            ambiguous_below = step.earliest_ns;
            break;
          }
      }
    }
    // The exceptions: not placed by the recording order and stamped where old and new readings
    // overlap (either side), or after a step of unknown size before the clock is good again.
    std::int64_t exception_below = std::numeric_limits<std::int64_t>::min();
    if (boundary == start) exception_below = ambiguous_below;
    if (!step.size_ns) exception_below = std::max(exception_below, good_again(samples, step.at_ns));
    for (std::size_t k = boundary; k < n && suffix_min[k] < exception_below; ++k)
      if (t(k) < exception_below) exceptions.emplace_back(k, s);
    boundaries.push_back(boundary);
    out.first_after.push_back(boundary < n ? seq(boundary) : -1);
    from = boundary;
  }
  free_vector(suffix_min);
  std::sort(exceptions.begin(), exceptions.end());
  // Running totals over the first j steps of the corrections a step of known size makes.
  std::vector<std::int64_t> total_shift(steps.size() + 1, 0), total_max(steps.size() + 1, 0);
  std::vector<double> total_var(steps.size() + 1, 0.0);
  std::vector<std::size_t> sized(steps.size() + 1, 0);  // steps of known size among the first j
  for (std::size_t j = 0; j < steps.size(); ++j) {
    const auto& step = steps[j];
    total_shift[j + 1] = total_shift[j], total_max[j + 1] = total_max[j], total_var[j + 1] = total_var[j];
    sized[j + 1] = sized[j];
    if (!step.size_ns) continue;
    total_shift[j + 1] += *step.size_ns;
    total_max[j + 1] = add_bound(total_max[j], step.size_max_ns);
    const auto est = static_cast<double>(step.size_est_ns);
    total_var[j + 1] += step.size_est_ns == store::kUnknownSize ? 0.0 : est * est;
    ++sized[j + 1];
  }
  std::vector<std::int64_t> shift(n, 0);  // by recording position
  std::vector<StepMark> mark(n, StepMark::none);
  std::vector<std::uint32_t> applied(n, 0);  // steps acting on the event (without exceptions: all corrected)
  {
    std::size_t m = 0, e = 0;
    for (std::size_t k = 0; k < n; ++k) {
      while (m < boundaries.size() && boundaries[m] <= k) ++m;
      applied[k] = static_cast<std::uint32_t>(m);
      shift[k] = total_shift[m];
      if (sized[m] > 0) mark[k] = StepMark::corrected;
      for (; e < exceptions.size() && exceptions[e].first == k; ++e) {
        const auto& step = steps[exceptions[e].second];
        mark[k] = StepMark::unknown;
        if (step.size_ns) shift[k] -= *step.size_ns;  // this step's correction is not made
      }
    }
  }
  // A corrected event's bounds: those of every step acting on it (an event with an exception is
  // marked unknown and carries none).
  for (std::size_t j = 0; j <= steps.size(); ++j)
    out.bounds.push_back({total_max[j], std::llround(std::sqrt(total_var[j]))});
  const bool any_corrected = std::find(mark.begin(), mark.end(), StepMark::corrected) != mark.end();
  const bool any_marked = any_corrected || std::find(mark.begin(), mark.end(), StepMark::unknown) != mark.end();

  const auto count = [&](StepMark m) {
    if (m == StepMark::corrected) ++out.corrected;
    if (m == StepMark::unknown) ++out.unknown;
  };
  // Apply. In recording order the corrected stamps nearly always stay in time order (the correction
  // undoes what the step did to the order): then they are written in place and the marks kept as
  // they are, without the re-sort's five arrays of n (m2mlat stats's peak on a kernel log with steps).
  bool stays_sorted = order.empty();
  for (std::size_t k = 1; k < n && stays_sorted; ++k) stays_sorted = t(k - 1) - shift[k - 1] <= t(k) - shift[k];
  if (stays_sorted) {
    for (std::size_t k = 0; k < n; ++k) {
      side.t_ns[k] -= shift[k];
      count(mark[k]);
      if (mark[k] != StepMark::corrected) applied[k] = 0;
    }
    if (any_marked) out.mark = std::move(mark);
    if (any_corrected) out.bound_of = std::move(applied);
    return out;
  }
  // Else re-sort by corrected time (filling the seq column with positions when there was none).
  if (side.seq.empty()) {
    side.seq.resize(n);
    std::iota(side.seq.begin(), side.seq.end(), std::int64_t{0});
  }
  if (order.empty()) {
    order.resize(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
  }
  std::vector<std::int64_t> corrected(n);
  for (std::size_t k = 0; k < n; ++k) corrected[order[k]] = side.t_ns[order[k]] - shift[k];
  free_vector(shift);
  std::vector<std::size_t> by_time(n);
  std::iota(by_time.begin(), by_time.end(), std::size_t{0});
  std::vector<std::size_t> position(n);  // recording position of each original index
  for (std::size_t k = 0; k < n; ++k) position[order[k]] = k;
  std::stable_sort(by_time.begin(), by_time.end(), [&](auto a, auto b) { return corrected[a] < corrected[b]; });
  store::Timestamps sorted{side.clock, {}, {}};
  sorted.seq.reserve(n);
  sorted.t_ns.reserve(n);
  if (any_marked) out.mark.reserve(n);
  if (any_corrected) out.bound_of.reserve(n);
  for (auto i : by_time) {
    const std::size_t k = position[i];
    sorted.seq.push_back(side.seq[i]);
    sorted.t_ns.push_back(corrected[i]);
    if (any_marked) out.mark.push_back(mark[k]);
    if (any_corrected) out.bound_of.push_back(mark[k] == StepMark::corrected ? applied[k] : 0);
    count(mark[k]);
  }
  side = std::move(sorted);
  return out;
}

void flag_events_after_steps(std::span<core::Event> events, const std::string& node,
                             std::span<const store::ClockSample> samples) {
  store::Timestamps side;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (events[i].node != node) continue;
    if (side.t_ns.empty()) side.clock = events[i].time.clock();
    side.seq.push_back(static_cast<std::int64_t>(i));
    side.t_ns.push_back(events[i].time.ns());
  }
  if (side.t_ns.empty()) return;
  const auto steps = steps_of(samples, side.clock);
  for (const auto seq : correct_side(side, steps, samples).first_after)
    if (seq >= 0) events[static_cast<std::size_t>(seq)].flags |= core::kFlagAfterClockStep;
}

std::vector<store::ClockStep> followed_steps(std::span<const store::ClockStep> stepped,
                                             std::span<const store::ClockSample> follower) {
  std::vector<store::ClockStep> out;
  std::vector<const store::ClockSample*> daemon;  // the follower's daemon samples, by time
  for (const auto& s : follower)
    if (s.source != store::kStepSource && s.source != "adjtimex" && s.synchronised) daemon.push_back(&s);
  std::stable_sort(daemon.begin(), daemon.end(),
                   [](const auto* a, const auto* b) { return a->time.ns() < b->time.ns(); });
  for (const auto& step : stepped) {
    if (!step.size_ns) continue;
    const std::int64_t size = *step.size_ns;
    const std::int64_t magnitude = std::llabs(size);
    // Its usual |offset| and error estimate before the step: a jump must stand far above them.
    std::vector<std::int64_t> offsets, estimates;
    auto it = daemon.begin();
    // The follower reads the old timescale until it follows: the step's moment there is earliest -
    // size; a sample taken a little before it (the two clocks differ) shows nothing, so it may count.
    const std::int64_t from_ns = std::min(step.earliest_ns, step.earliest_ns - size) - magnitude;
    for (; it != daemon.end() && (*it)->time.ns() < from_ns; ++it) {
      offsets.push_back(std::llabs((*it)->offset_ns));
      estimates.push_back(std::max<std::int64_t>((*it)->est_error_ns, 0));
    }
    const auto median = [](std::vector<std::int64_t>& v) -> std::int64_t {
      if (v.empty()) return 0;
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      return v[v.size() / 2];
    };
    const std::int64_t usual = median(offsets);
    const std::int64_t usual_est = median(estimates);
    if (8 * usual >= magnitude) continue;  // the step would not stand out of its noise
    // Its daemon measures the jump at its next poll and slews it away over the next ones: among its
    // next three samples, an offset far beyond its usual one (either sign: behind, then overshooting)
    // or an error estimate jumped up by an eighth of the step says its reference moved with the step.
    const auto horizon = it + std::min<std::ptrdiff_t>(3, daemon.end() - it);
    const auto disturbed = std::find_if(it, horizon, [&](const auto* s) {
      return std::llabs(s->offset_ns) > std::max(8 * usual, magnitude / 16) ||
             (!estimates.empty() && s->est_error_ns - usual_est > magnitude / 8);
    });
    if (disturbed == horizon) continue;
    store::ClockStep follow;
    follow.origin = "followed";
    follow.size_ns = size;
    follow.earliest_ns = step.earliest_ns;
    // Back in step: two samples in a row (or the last) within max(step / 16, 4 x usual).
    const std::int64_t close = std::max(magnitude / 16, 4 * usual);
    const auto within = [&](auto k) { return k == daemon.end() || std::llabs((*k)->offset_ns) <= close; };
    auto back = disturbed + 1;
    while (back != daemon.end() && !(within(back) && within(back + 1))) ++back;
    if (back == daemon.end()) {
      follow.at_ns = std::numeric_limits<std::int64_t>::max() / 2;  // never back in step: flagged to the end
    } else {
      // Stamps in [earliest, back) are mid-slew (flagged); from `back` on the follower reads the stepped
      // board's new timescale: the overlap rule of correct_side places that boundary at at_ns - size.
      follow.at_ns = (*back)->time.ns() + size;
      std::int64_t left = std::llabs((*back)->offset_ns);
      if (back + 1 != daemon.end()) left = std::max<std::int64_t>(left, std::llabs((*(back + 1))->offset_ns));
      // The offset left is what its daemon measured: twice that bounds what the clock still had.
      follow.size_max_ns = add_bound(step.size_max_ns, 2 * left);
      const auto est = static_cast<double>(step.size_est_ns == store::kUnknownSize ? 0 : step.size_est_ns);
      follow.size_est_ns = std::llround(std::sqrt(est * est + static_cast<double>(left) * static_cast<double>(left)));
    }
    out.push_back(follow);
  }
  return out;
}

ScenarioSteps correct_scenario(ScenarioInput& input, std::span<const store::ClockSample> cause_samples,
                               std::span<const store::ClockSample> effect_samples) {
  ScenarioSteps out;
  auto cause_steps = steps_of(cause_samples, input.clock);
  auto effect_steps = steps_of(effect_samples, input.clock);
  // A board whose daemon follows the other board (co-referenced: the vehicle's reference is the
  // operator's clock) is pulled onto a step of that board: it takes the step too, after its slew.
  auto cause_follow = followed_steps(effect_steps, cause_samples);
  auto effect_follow = followed_steps(cause_steps, effect_samples);
  const auto merge = [](std::vector<store::ClockStep>& into, std::vector<store::ClockStep>& more) {
    into.insert(into.end(), more.begin(), more.end());
    std::stable_sort(into.begin(), into.end(), [](const auto& a, const auto& b) { return a.earliest_ns < b.earliest_ns; });
  };
  merge(cause_steps, cause_follow);
  merge(effect_steps, effect_follow);
  out.cause = correct_side(input.cause, cause_steps, cause_samples);
  out.effect = correct_side(input.effect, effect_steps, effect_samples);
  return out;
}

}  // namespace m2mlat::analysis
