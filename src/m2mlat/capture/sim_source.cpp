// Chunks from the generator, one side kept, handed over at once or paced on CLOCK_MONOTONIC.
#include "m2mlat/capture/sim_source.hpp"

#include <fmt/format.h>

#include "m2mlat/capture/recorder.hpp"

namespace m2mlat::capture {

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
  }
  const auto now = monotonic_now();
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
    out.events.push_back(ready_.front());
    ready_.pop_front();
    ++taken;
  }
  out.finished = ready_.empty() && generator_->done();
}

std::vector<std::string> SimSource::describe() const {
  return {fmt::format("{}: simulated rig '{}' (seed {}), the {} board's edges, {}", options_.channel,
                      options_.config.scenario, options_.config.seed, core::to_string(options_.side),
                      options_.paced ? "paced in real time" : "as fast as possible")};
}

}  // namespace m2mlat::capture
