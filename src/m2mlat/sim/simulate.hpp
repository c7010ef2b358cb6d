// A whole simulated run in memory: both nodes' events, their truth, the passes, the true pairs,
// the manoeuvres and the clock samples. Convenient for tests, demos and small campaigns; for long
// runs (millions of events) stream with Generator instead.
#pragma once

#include <vector>

#include "m2mlat/sim/generator.hpp"
#include "m2mlat/sim/rig_config.hpp"
#include "m2mlat/sim/truth.hpp"

namespace m2mlat::sim {

struct Simulation {
  RigConfig config;
  std::vector<core::Event> cause_events;
  std::vector<core::Event> effect_events;
  std::vector<EventTruth> cause_truth;   // parallel to cause_events
  std::vector<EventTruth> effect_truth;  // parallel to effect_events
  std::vector<PassTruth> passes;         // every pass, by index (PassTruth::index == position)
  std::vector<TruePair> pairs;           // passes detected on both sides, by pass index
  std::vector<ManoeuvreTruth> manoeuvres;
  std::vector<ClockSample> clock_samples;

  const std::vector<core::Event>& events(core::Role role) const {
    return role == core::Role::effect ? effect_events : cause_events;
  }
  const std::vector<EventTruth>& truth(core::Role role) const {
    return role == core::Role::effect ? effect_truth : cause_truth;
  }
};

// Runs the whole simulation. Throws core::Error(usage) if the configuration is invalid.
Simulation simulate(const RigConfig& config);

}  // namespace m2mlat::sim
