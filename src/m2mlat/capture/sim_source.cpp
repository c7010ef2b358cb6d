// Chunks from the generator, one side kept, handed over at once or paced on CLOCK_MONOTONIC.
#include "m2mlat/capture/sim_source.hpp"

#include <fmt/format.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/store/clock_step.hpp"

namespace m2mlat::capture {

store::ClockSample sim_clock_sample(const sim::ClockSample& s, std::int64_t session_id,
                                    std::string_view reference) {
  if (s.step.count() != 0) {
    // The simulated twin of the clock monitor's step record, its size exact and its time known.
    store::ClockStep step;
    step.at_ns = s.true_time.ns() + s.error.count();
    step.earliest_ns = step.at_ns;
    step.size_ns = s.step.count();
    step.size_max_ns = step.size_est_ns = 0;
    step.origin = "sim";
    auto out = store::step_clock_sample(step);
    out.session_id = session_id;
    return out;
  }
  store::ClockSample out;
  out.session_id = session_id;
  // The sample is taken on the node's own clock: true time plus that clock's error.
  out.time = core::TimePoint::from_ns(core::Clock::realtime, s.true_time.ns() + s.error.count());
  out.source = "sim";
  out.offset_ns = s.estimated_offset.count();
  const bool synced = s.error_bound != core::Duration::max();
  out.max_error_ns = synced ? s.error_bound.count() : std::numeric_limits<std::int64_t>::max();
  out.est_error_ns = synced ? s.error_estimate.count() : std::numeric_limits<std::int64_t>::max();
  out.synchronised = synced;
  // Not the model's true error: a real daemon cannot see it, and nothing downstream may use it.
  out.detail_json = nlohmann::json{{"rms_offset_ns", s.rms_offset.count()},
                                   {"skew_ppm", s.skew_ppm},
                                   {"ref_name", std::string(reference)}}
                        .dump();
  return out;
}

std::string sim_reference(const sim::RigConfig& config, core::Role role) {
  return role == core::Role::effect && config.sync.mode == sim::SyncMode::co_referenced ? config.cause_node
                                                                                        : std::string();
}

SimSource::SimSource(SimSourceOptions options)
    : options_(std::move(options)), generator_(std::make_unique<sim::Generator>(options_.config)) {
  if (options_.side == core::Role::observer) options_.side = core::Role::effect;
}

core::Duration SimSource::poll_interval() const {
  return options_.paced ? core::Duration{std::chrono::milliseconds(5)} : core::Duration{0};
}

void SimSource::read(ReadResult& out, std::size_t max_events) {
  while (ready_.size() < max_events && !generator_->done()) {
    if (!generator_->next(chunk_, 4096)) break;
    for (auto& event : chunk_.events(options_.side)) {
      event.node = options_.node;
      event.channel = options_.channel;
      ready_.push_back(std::move(event));
    }
    for (const auto& sample : chunk_.clock_samples)
      if (sample.node == options_.side)
        clock_ready_.push_back(sim_clock_sample(sample, 0, sim_reference(options_.config, options_.side)));
  }
  const auto now = core::monotonic_now();
  std::size_t taken = 0;
  while (taken < max_events && !ready_.empty()) {
    const auto& next = ready_.front();
    if (options_.paced) {
      if (!have_origin_) {
        have_origin_ = true;
        origin_event_ns_ = next.time.ns();
        origin_wall_ = now;
      }
      if (core::Duration{next.time.ns() - origin_event_ns_} > now - origin_wall_) break;
    }
    handed_ns_ = next.time.ns();
    out.events.push_back(ready_.front());
    ready_.pop_front();
    ++taken;
  }
  out.finished = ready_.empty() && generator_->done();
  // The daemons' readings up to the simulated time reached: paced, the wall clock's; unpaced, the
  // last event's; all that are left at the end.
  if (options_.paced && have_origin_) handed_ns_ = origin_event_ns_ + (now - origin_wall_).count();
  while (!clock_ready_.empty() && (out.finished || clock_ready_.front().time.ns() <= handed_ns_)) {
    out.clock_samples.push_back(clock_ready_.front());
    clock_ready_.pop_front();
  }
}

std::vector<std::string> SimSource::describe() const {
  return {fmt::format("{}: simulated rig '{}' (seed {}), the {} board's edges, {}", options_.channel,
                      options_.config.scenario, options_.config.seed, core::to_string(options_.side),
                      options_.paced ? "paced in real time" : "as fast as possible")};
}

}  // namespace m2mlat::capture
