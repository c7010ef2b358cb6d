// Clock steps carried into the latency samples. A step of one board's CLOCK_REALTIME (found by any
// detector: store/clock_step.hpp) moves every later stamp of that board by the step's size, so
// without this every later latency would be off by exactly that size.
//
// The rule, per board, for each step in time order, over the board's events in recording order
// (store sequence number, or position in the file):
//   - events stamped before the step's window (t < earliest_ns) are before it;
//   - a step of known size s: the events after it are brought back onto the timescale before the
//     step (t - s), so that the board keeps one timescale over the run. This assumes what was true
//     before the step stays true after it: the other board did not move, and the step is the whole
//     change (the daemon did not slew it away afterwards). A corrected event carries the size's
//     uncertainty (ClockStep::size_max_ns, size_est_ns), summed over the steps applied to it.
//     An event whose stamp could lie on either side (t in [earliest_ns, at_ns - s), where old and
//     new readings overlap) is not corrected but marked unknown; a step back (s < 0) seen in the
//     recording order as a stamp lower than the one before it places the events exactly.
//   - a step of unknown size: every later event is marked unknown until the board is known good
//     again: a synchronised clock sample (not a step) taken at or after the step.
// A pair with an event marked unknown is flagged "after clock step" and left out of the statistics
// (ScenarioResult::in_statistics); a corrected pair stays in, with the step's uncertainty.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"

#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::analysis {

// Leaves out of each side the events whose stamps `unknown` (by node) puts on no known clock, and
// counts them by reason in input.cause_unknown_clock / effect_unknown_clock. Ids stay the events'
// own (a side whose ids were positions gets its seq column). Runs before correct_scenario: the ranges
// are raw stamps.
void leave_out_unknown_clock(ScenarioInput& input,
                             const std::map<std::string, std::vector<store::UnknownClock>>& unknown);

// Values are shown in exports: never renumber.
enum class StepMark : std::uint8_t { none = 0, corrected = 1, unknown = 2 };

// The pairing::PairFlag bit of a pair's StepMark (kPairStepCorrected, kPairAfterClockStep or none).
std::uint32_t pair_flags(StepMark mark);

// Per event of one side (parallel to its Timestamps after correct_side re-sorted them).
struct SideSteps {
  std::vector<StepMark> mark;  // empty: no event of this side is corrected or unknown
  // A corrected event's step bounds: bounds[bound_of[i]]. Kept as an index (4 bytes an event, and
  // none on a side without corrected events) because the bounds are the running sums over the first
  // j steps, so a board has at most steps + 1 of them; 16 bytes an event were a fifth of `m2mlat
  // stats`'s peak memory on a kernel log with steps.
  struct Bound {
    std::int64_t max_ns = 0;  // sum of the applied steps' size bounds, ns
    std::int64_t est_ns = 0;  // ... and their standard uncertainties added in quadrature, ns
  };
  std::vector<std::uint32_t> bound_of;  // per event, parallel to mark; empty when corrected == 0
  std::vector<Bound> bounds;
  std::size_t steps = 0;                  // steps of this board
  std::size_t corrected = 0, unknown = 0;  // events so marked
  std::vector<std::int64_t> first_after;   // per step: the seq of the first event recorded after it (-1: none)
  // The steps the board's kernel log cannot show (kernel_log_steps.hpp).
  LogClockLimits limits;
  StepMark at(std::size_t i) const { return i < mark.size() ? mark[i] : StepMark::none; }
  // The bounds of event i when it is corrected, else {0, 0}.
  Bound bound(std::size_t i) const {
    return at(i) == StepMark::corrected && i < bound_of.size() ? bounds[bound_of[i]] : Bound{};
  }
};

// The steps among a board's clock samples (source "step"), in time order.
std::vector<store::ClockStep> steps_of(std::span<const store::ClockSample> samples, core::Clock clock);

// Applies the rule above to one side: corrects side.t_ns in place and returns the marks. When the
// corrected stamps are out of time order (or the side out of recording order), it re-sorts the side by
// time, filling side.seq with positions first when it was empty. `samples` are the board's
// other clock samples (what says the clock is good again after a step of unknown size).
SideSteps correct_side(store::Timestamps& side, std::span<const store::ClockStep> steps,
                       std::span<const store::ClockSample> samples);

// Sets core::kFlagAfterClockStep on the first event of each node recorded after each of its steps
// (by correct_side's rule; events in file order), given each node's clock samples.
void flag_events_after_steps(std::span<core::Event> events, const std::string& node,
                             std::span<const store::ClockSample> samples);

// The steps a board takes over from the other board's steps of known size: when one of its daemon's
// next three samples after such a step shows it behind (ahead) by more than half the step, and the
// step stands 8 times above the board's usual |offset| (the median before it), its daemon follows the
// stepped board (in a co-referenced rig the vehicle's reference is the operator's clock) and slews
// onto the new timescale. Its stamps from the step until its daemon's offset is back within
// max(step / 16, 4 x usual) are flagged; from there on they are corrected by the same size (the
// step's uncertainty plus the offset left then). Never back: flagged to the end. origin "followed".
std::vector<store::ClockStep> followed_steps(std::span<const store::ClockStep> stepped,
                                             std::span<const store::ClockSample> follower);

// Both sides of a scenario, each from its board's clock samples (steps and others), with the steps
// each takes over from the other (followed_steps).
struct ScenarioSteps {
  SideSteps cause, effect;
  std::size_t steps() const { return cause.steps + effect.steps; }
  std::size_t fast_slew_places() const { return cause.limits.fast_slew_places + effect.limits.fast_slew_places; }
  bool limited() const { return cause.limits.any() || effect.limits.any(); }  // a note to give
};
ScenarioSteps correct_scenario(ScenarioInput& input, std::span<const store::ClockSample> cause_samples,
                               std::span<const store::ClockSample> effect_samples);

}  // namespace m2mlat::analysis
