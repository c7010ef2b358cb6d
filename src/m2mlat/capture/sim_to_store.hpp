// Recording a simulated run into a store exactly as two boards would: one session per node (the
// operator's with role cause, the vehicle's with role effect), its events in batches, and each
// node's clock state as clock samples (source "sim"). The demo, `m2mlat simulate --store` and the
// tests use this, so the simulated path goes through the same store as a real recording.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "m2mlat/sim/full_loop.hpp"
#include "m2mlat/sim/generator.hpp"
#include "m2mlat/sim/rig_config.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::capture {

struct RecordedRun {
  std::int64_t cause_session = 0;
  std::int64_t effect_session = 0;
  std::int64_t cause_events = 0;
  std::int64_t effect_events = 0;
};

// Called after every chunk with the events produced so far (both nodes): for progress lines.
using ChunkObserver = std::function<void(const sim::Chunk&, std::int64_t events_so_far)>;

// Streams the run of `config` into `store` (bounded memory whatever the run's length). `label` names
// the sessions; the scenario is config.scenario. `observer`, if set, sees every chunk (e.g. to keep
// the truth) and may throw to stop the run. Sessions are closed at the last event's time. The run is
// one transaction (store::WholeWrite): recorded whole, or not at all when anything throws or the
// process is killed.
RecordedRun record_simulation(store::Store& store, const sim::RigConfig& config, const std::string& label,
                              const ChunkObserver& observer = {});

// The simulated full loop (sim/full_loop.hpp) recorded as the two boards of a real one would record
// it: the station board ("station", role cause) one session with its gyroscope's raw trace (channel
// "gyro") and the phototransistor's edges (channel "photo", falling); the vehicle board ("vehicle",
// role effect) one session with its gyroscope's trace and a second one, as `m2mlat led` makes, with
// the LED's writes (channel "led", rising, flag commanded) and the writes' largest half-width in its
// configuration (store::kConfigLedBound). Each session carries its board's clock samples
// (sim::board_clock_samples, source "sim"). All on Clock::simulated, scenario `scenario`.
enum class FullLoopBoards : std::uint8_t { station, vehicle, both };
struct RecordedFullLoop {
  std::int64_t station_session = 0, vehicle_session = 0, led_session = 0;  // 0: not recorded here
};
// Throws core::Error(usage) for a single_board run (no gyroscopes: nothing to chain from a store).
RecordedFullLoop record_full_loop(store::Store& store, const sim::FullLoopRun& run, FullLoopBoards boards,
                                  const std::string& label, const std::string& scenario);

}  // namespace m2mlat::capture
