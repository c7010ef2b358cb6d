// The simulated rig's network and software stages, with their truth: for each magnet pass, the
// command that carries it on its way from the operator's wheel to the vehicle's, marked where a real
// rig would mark it (docs/breakdown.md, "The simulator"):
//
//   cause edge -> operator:command  operator software: the wheel read, the command built
//              -> operator:send     send: the command through the socket onto the wire
//              -> vehicle:receive   network one-way (lost packets and stalls included)
//              -> vehicle:apply     vehicle software: control-loop wait, set point written
//              -> effect edge       actuator: dead time, and the wheel turning to the magnet
//
// The durations are the manoeuvre's own (ManoeuvreTruth: command, network, execution delay), so the
// stages are those the simulated M2M is made of; the send stage is a part of the command delay drawn
// on its own stream (the other streams do not move). Each marker is stamped with its board's
// simulated CLOCK_REALTIME (the same clock model as the events, queried afresh in time order), so a
// breakdown on the simulator meets the boards' clock errors as a real one does.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/sim/simulate.hpp"

namespace m2mlat::sim {

inline constexpr std::size_t kStageMarkerCount = 4;
// The markers' names, in order along the chain, and on which board each is taken.
inline constexpr std::array<std::string_view, kStageMarkerCount> kStageMarkerNames = {"command", "send", "receive",
                                                                                       "apply"};
inline constexpr std::array<core::Role, kStageMarkerCount> kStageMarkerBoards = {
    core::Role::cause, core::Role::cause, core::Role::effect, core::Role::effect};

// One marker of one pass's command.
struct StageMark {
  std::int64_t pass = 0;       // PassTruth::index: also the command's key
  std::size_t point = 0;       // index into kStageMarkerNames
  core::TimePoint true_time;   // Clock::simulated
  core::TimePoint stamp;       // Clock::realtime: the board's reading at true_time
};

// The truth of one pass's chain.
struct StageChainTruth {
  std::int64_t pass = 0;
  // True times of the four markers (ns since the epoch, Clock::simulated), each clamped to at most
  // the pass's true effect time so that the chain stays in order in every preset.
  std::array<std::int64_t, kStageMarkerCount> true_ns{};
  // The board's clock error (reading - true time, ns) at each marker.
  std::array<std::int64_t, kStageMarkerCount> clock_error_ns{};
};

struct StageMarkerOptions {
  double drop_probability = 0;  // each marker is left out with this chance (a lost log line)
};

struct StageMarkers {
  std::vector<StageMark> marks;          // by true time; dropped ones are not here
  std::vector<StageChainTruth> chains;   // one per pass, by pass index
  std::size_t dropped = 0;
};

// The stage markers of a whole simulated run. Throws core::Error(usage) for a drop probability
// outside [0, 1].
StageMarkers stage_markers(const Simulation& run, const StageMarkerOptions& options = {});

// The stage rule (analysis/stage_rule.hpp) that cuts a simulated event with these markers: one stage
// per marker, then the actuator, the boards named as the run names them.
std::string stage_rule_text(std::string_view cause_node, std::string_view effect_node);

}  // namespace m2mlat::sim
