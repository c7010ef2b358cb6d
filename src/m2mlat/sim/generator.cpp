// The streaming simulator: merges the planned manoeuvres' edges, the sensors' imperfections and
// the clocks into each node's event stream, in true-time order. See generator.hpp.
#include "m2mlat/sim/generator.hpp"

#include <algorithm>
#include <cmath>  // llround: exact
#include <limits>

namespace m2mlat::sim {

namespace {
constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
// The run ends this long after the last planned edge (or at the next manoeuvre's start, if later),
// so the last bounces and spurious edges have room.
constexpr std::int64_t kTailNs = 1'000'000'000;

const RigConfig& validated(const RigConfig& config) {
  validate(config);
  return config;
}
}  // namespace

void Chunk::clear() {
  cause_events.clear();
  effect_events.clear();
  cause_truth.clear();
  effect_truth.clear();
  cause_first_index = effect_first_index = 0;
  passes.clear();
  pairs.clear();
  manoeuvres.clear();
  clock_samples.clear();
}

Generator::Generator(const RigConfig& config)
    : config_(validated(config)),
      planner_(config_),
      clocks_(config_.cause_clock, config_.effect_clock, config_.sync, config_.start.ns(), config_.seed),
      cause_(core::Role::cause, config_.cause_sensor, config_.seed),
      effect_(core::Role::effect, config_.effect_sensor, config_.seed),
      end_ns_(kNever),
      next_sample_ns_(config_.start.ns()) {
  schedule_spurious(cause_, config_.start.ns());
  schedule_spurious(effect_, config_.start.ns());
}

void Generator::schedule_spurious(Side& side, std::int64_t after_ns) {
  Pending& p = side.spurious;
  p = Pending{};
  p.kind = EdgeKind::spurious;
  p.true_ns = side.sensor.next_spurious(after_ns);
  if (p.true_ns == kNever) {
    p.key_ns = kNever;
    return;
  }
  p.irq_ns = side.sensor.irq_latency();
  p.key_ns = p.true_ns + p.irq_ns;
  p.order = order_++;
}

void Generator::push_rising(Side& side, const Pending& like, std::int64_t true_ns, std::int64_t after_key_ns,
                            std::int64_t before_key_ns) {
  Pending r = like;
  r.edge = core::Edge::rising;
  r.true_ns = true_ns;
  // The kernel stamps a line's edges in the order they come: never before the falling edge it ends.
  r.key_ns = std::max(true_ns + side.sensor.rising_irq_latency(), after_key_ns + 1);
  if (r.key_ns >= before_key_ns) return;
  r.irq_ns = r.key_ns - true_ns;
  r.order = order_++;
  side.queue.push(r);
}

void Generator::push_edges(Side& side, std::int64_t true_ns, std::int64_t manoeuvre, std::int64_t pass,
                           std::int32_t magnet, bool detected) {
  if (!detected) return;
  Pending p;
  p.true_ns = true_ns;
  p.irq_ns = side.sensor.irq_latency();
  p.key_ns = true_ns + p.irq_ns;
  p.order = order_++;
  p.kind = EdgeKind::pass;
  p.manoeuvre = manoeuvre;
  p.pass = pass;
  p.magnet = magnet;
  side.queue.push(p);
  last_edge_ns_ = std::max(last_edge_ns_, true_ns);
  bounce_scratch_.clear();
  side.sensor.bounces(true_ns, bounce_scratch_);
  const bool both = side.sensor.both_edges();
  Pending previous = p;  // the falling edge a rising one ends
  for (std::int64_t t : bounce_scratch_) {
    p.true_ns = t;
    p.irq_ns = side.sensor.irq_latency();
    p.key_ns = t + p.irq_ns;
    p.order = order_++;
    p.kind = EdgeKind::bounce;
    side.queue.push(p);
    last_edge_ns_ = std::max(last_edge_ns_, t);
    // Chatter: the line back up half-way between two falling edges.
    if (both) push_rising(side, p, previous.true_ns + (t - previous.true_ns) / 2, previous.key_ns, p.key_ns);
    previous = p;
  }
  if (both) {
    Pending release = previous;
    release.kind = EdgeKind::release;
    // SensorConfig validation keeps the dwell longer than the bounce window: released after them.
    push_rising(side, release, true_ns + side.sensor.dwell(), previous.key_ns, kNever);
  }
}

void Generator::plan_manoeuvre(Chunk& chunk) {
  planner_.next(plan_);
  chunk.manoeuvres.push_back(plan_.truth);
  const std::int64_t manoeuvre = plan_.truth.index;
  for (const PlannedPass& planned : plan_.passes) {
    OpenPass open;
    open.truth.index = passes_planned_++;
    open.truth.manoeuvre = manoeuvre;
    open.truth.sweep = planned.sweep;
    open.truth.magnet = planned.magnet;
    open.truth.cause_time = true_time(planned.cause_ns);
    open.truth.effect_time = true_time(planned.effect_ns);
    const bool cause_sees = cause_.sensor.detects();
    const bool effect_sees = effect_.sensor.detects();
    open.waiting = (cause_sees ? 1 : 0) + (effect_sees ? 1 : 0);
    open_.push_back(open);
    push_edges(cause_, planned.cause_ns, manoeuvre, open.truth.index, planned.magnet, cause_sees);
    push_edges(effect_, planned.effect_ns, manoeuvre, open.truth.index, planned.magnet, effect_sees);
    last_edge_ns_ = std::max({last_edge_ns_, planned.cause_ns, planned.effect_ns});
  }
  if (!planner_.has_next()) end_ns_ = std::max(planner_.next_start_ns(), last_edge_ns_ + kTailNs);
  close_passes(chunk);  // passes missed on both sides are complete already
}

void Generator::sample_clocks_until(std::int64_t true_ns, Chunk& chunk) {
  const std::int64_t interval = config_.clock_sample_interval.count();
  // A configured clock step is recorded once, at its true time, in time order with the samples.
  const auto step_ns = [&](core::Role role) {
    const ClockConfig& c = role == core::Role::effect ? config_.effect_clock : config_.cause_clock;
    const bool pending = c.step.count() != 0 && !step_recorded_[role == core::Role::effect ? 1 : 0];
    return pending ? config_.start.ns() + c.step_at.count() : kNever;
  };
  while (true) {
    const std::int64_t next = std::min<std::int64_t>(
        {interval > 0 ? next_sample_ns_ : kNever, step_ns(core::Role::cause), step_ns(core::Role::effect)});
    if (next > true_ns) return;
    for (core::Role role : {core::Role::cause, core::Role::effect}) {
      if (step_ns(role) != next) continue;
      const ClockConfig& c = role == core::Role::effect ? config_.effect_clock : config_.cause_clock;
      const ClockState state = clocks_.at(role, next);
      ClockSample record;  // a step record, not a state: only what describes the step
      record.node = role;
      record.true_time = true_time(next);
      record.error = core::Duration{std::llround(state.error_ns)};
      record.estimated_offset = state.estimated_offset;
      record.error_bound = state.error_bound;
      record.step = c.step;
      chunk.clock_samples.push_back(record);
      step_recorded_[role == core::Role::effect ? 1 : 0] = true;
    }
    if (interval <= 0 || next_sample_ns_ != next) continue;
    for (core::Role role : {core::Role::cause, core::Role::effect}) {
      const ClockState state = clocks_.at(role, next_sample_ns_);
      chunk.clock_samples.push_back({role, true_time(next_sample_ns_),
                                     core::Duration{std::llround(state.error_ns)}, state.estimated_offset,
                                     state.error_bound, state.error_estimate, state.rms_offset,
                                     state.skew_ppm});
    }
    next_sample_ns_ += interval;
  }
}

void Generator::emit(Side& side, const Pending& edge, Chunk& chunk) {
  sample_clocks_until(edge.key_ns, chunk);
  const core::Duration error = clocks_.error(side.role, edge.key_ns);
  const std::int64_t stamp = edge.key_ns + error.count();
  const std::int64_t index = side.emitted++;
  const auto seqno = static_cast<std::uint64_t>(side.emitted);
  const std::string& node = side.role == core::Role::effect ? config_.effect_node : config_.cause_node;
  // The first edge after the board's clock step says so, as a recorder's would.
  const ClockConfig& clock = side.role == core::Role::effect ? config_.effect_clock : config_.cause_clock;
  const std::int64_t step_ns = config_.start.ns() + clock.step_at.count();
  const bool after_step = clock.step.count() != 0 && side.last_key_ns < step_ns && step_ns <= edge.key_ns;
  side.last_key_ns = edge.key_ns;
  chunk.events(side.role).push_back(
      core::Event{node, config_.channel, edge.edge, core::TimePoint::from_ns(core::Clock::realtime, stamp),
                  seqno, seqno, core::kFlagSimulated | (after_step ? core::kFlagAfterClockStep : 0u)});
  chunk.truth(side.role).push_back(EventTruth{edge.kind, edge.manoeuvre, edge.pass, edge.magnet,
                                              true_time(edge.true_ns), core::Duration{edge.irq_ns}, error});
  if (edge.kind != EdgeKind::pass) return;  // a pass's rising edge is kind release
  OpenPass& open = open_[static_cast<std::size_t>(edge.pass - first_open_pass_)];
  if (side.role == core::Role::effect) {
    open.truth.effect_event = index;
    open.effect_stamp_ns = stamp;
  } else {
    open.truth.cause_event = index;
    open.cause_stamp_ns = stamp;
  }
  --open.waiting;
  close_passes(chunk);
}

void Generator::close_passes(Chunk& chunk) {
  while (!open_.empty() && open_.front().waiting == 0) {
    const OpenPass& open = open_.front();
    chunk.passes.push_back(open.truth);
    if (open.truth.cause_event >= 0 && open.truth.effect_event >= 0)
      chunk.pairs.push_back(TruePair{open.truth.index, open.truth.cause_event, open.truth.effect_event,
                                     open.truth.true_latency(),
                                     core::Duration{open.effect_stamp_ns - open.cause_stamp_ns}});
    open_.pop_front();
    ++first_open_pass_;
  }
}

bool Generator::next(Chunk& chunk, std::size_t max_events) {
  chunk.clear();
  chunk.cause_first_index = cause_.emitted;
  chunk.effect_first_index = effect_.emitted;
  if (done_) return false;
  max_events = std::max<std::size_t>(max_events, 1);
  while (chunk.event_count() < max_events) {
    // The earliest waiting edge of either node (queued, or the next spurious one before the end).
    Side* from = nullptr;
    const Pending* best = nullptr;
    bool spurious = false;
    for (Side* side : {&cause_, &effect_}) {
      if (!side->queue.empty() && (best == nullptr || *best > side->queue.top())) {
        from = side;
        best = &side->queue.top();
        spurious = false;
      }
      if (side->spurious.key_ns != kNever && side->spurious.true_ns < end_ns_ &&
          (best == nullptr || *best > side->spurious)) {
        from = side;
        best = &side->spurious;
        spurious = true;
      }
    }
    // Plan the next manoeuvre before emitting anything later than its start: its edges may come first.
    if (planner_.has_next() && (best == nullptr || planner_.next_start_ns() <= best->key_ns)) {
      plan_manoeuvre(chunk);
      continue;
    }
    if (best == nullptr) {
      sample_clocks_until(end_ns_ - 1, chunk);
      close_passes(chunk);
      done_ = true;
      break;
    }
    const Pending edge = *best;
    if (spurious) {
      schedule_spurious(*from, edge.true_ns);
      // Interference on a line recorded with both edges: a pulse of microseconds.
      if (from->sensor.both_edges())
        push_rising(*from, edge, edge.true_ns + from->sensor.interference_width(), edge.key_ns, kNever);
    } else {
      from->queue.pop();
    }
    emit(*from, edge, chunk);
  }
  return chunk.event_count() > 0 || !chunk.manoeuvres.empty() || !chunk.passes.empty() ||
         !chunk.clock_samples.empty();
}

}  // namespace m2mlat::sim
