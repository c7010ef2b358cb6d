// The simulated source: one node's side of the simulated rig (sim::Generator), for demonstrations
// and for trying the two-board workflow without hardware. The events keep the simulator's
// timestamps, seqno and the simulated flag; they are renamed to the recorder's node and channel.
// Paced, an event is handed over when as much wall time has passed since the first one as
// simulated time did (the timestamps stay the simulator's); unpaced, as fast as the store takes them.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "m2mlat/capture/source.hpp"
#include "m2mlat/core/event.hpp"
#include "m2mlat/sim/generator.hpp"
#include "m2mlat/sim/rig_config.hpp"

namespace m2mlat::capture {

struct SimSourceOptions {
  std::string node;
  std::string channel = "wheel";
  core::Role side = core::Role::effect;  // which board of the rig: cause (operator) or effect (vehicle)
  sim::RigConfig config;                 // the simulated run (a preset, maybe with overrides)
  bool paced = false;                    // real-time pacing
};

// A simulated daemon's reading as the store keeps it (source "sim"), with only what a real daemon
// reports: taken on the node's own clock, offset_ns = its last measured offset, max_error = its bound
// (root delay / 2 + root dispersion), est_error = its standard uncertainty (k = 1) of the offset
// from its reference (sim::ClockState::error_estimate); both unbounded when not synchronised.
// detail_json, in chrony's tracking names: rms_offset_ns, skew_ppm, and ref_name = `reference`, the
// node whose clock this one follows (empty: its own time servers).
store::ClockSample sim_clock_sample(const sim::ClockSample& sample, std::int64_t session_id,
                                    std::string_view reference = {});
// The node whose clock `role`'s daemon follows in `config`: the cause node for the effect board of
// a co-referenced rig, else none (empty).
std::string sim_reference(const sim::RigConfig& config, core::Role role);

class SimSource final : public Source {
 public:
  explicit SimSource(SimSourceOptions options);
  void read(ReadResult& out, std::size_t max_events) override;
  int fd() const override { return -1; }
  core::Duration poll_interval() const override;
  std::vector<std::string> describe() const override;
  std::vector<std::string> channels() const override { return {options_.channel}; }

 private:
  SimSourceOptions options_;
  std::unique_ptr<sim::Generator> generator_;
  sim::Chunk chunk_;
  std::deque<core::Event> ready_;
  std::deque<store::ClockSample> clock_ready_;  // this side's daemon readings, by time
  bool have_origin_ = false;
  std::int64_t origin_event_ns_ = 0;  // the first event's simulated timestamp
  core::Duration origin_wall_{0};     // CLOCK_MONOTONIC when it was handed over
  std::int64_t handed_ns_ = INT64_MIN;  // simulated time handed over so far (unpaced: the last event's)
};

}  // namespace m2mlat::capture
