// Simulated run -> store, chunk by chunk; one transaction per node per chunk.
#include "m2mlat/capture/sim_to_store.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/sim_source.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::capture {

namespace {

// The simulation's settings that a reader of the session needs (the full config is reproducible
// from the preset, the seed and the software version).
std::string config_json(const sim::RigConfig& config, core::Role role) {
  nlohmann::json j{{"source", "sim"},
                   {"preset", config.scenario},
                   {"seed", config.seed},
                   {"role", core::to_string(role)},
                   {"manoeuvres", config.manoeuvres},
                   {"duration_ns", config.duration.count()},
                   {"magnets_deg", config.magnets_deg},
                   {"channel", config.channel}};
  return j.dump();
}

}  // namespace

RecordedRun record_simulation(store::Store& store, const sim::RigConfig& config, const std::string& label,
                              const ChunkObserver& observer) {
  sim::Generator generator(config);
  RecordedRun run;
  store::WholeWrite whole(store);  // the scenario whole or not at all (an observer may throw to stop)
  auto begin = [&](const std::string& node, core::Role role) {
    store::Session s;
    s.label = label;
    s.scenario = config.scenario;
    s.node = node;
    s.role = role;
    s.config_json = config_json(config, role);
    s.start = config.start;
    return store.begin_session(s);
  };
  run.cause_session = begin(config.cause_node, core::Role::cause);
  run.effect_session = begin(config.effect_node, core::Role::effect);

  core::TimePoint last = config.start;
  sim::Chunk chunk;
  std::int64_t total = 0;
  while (generator.next(chunk)) {
    for (auto role : {core::Role::cause, core::Role::effect}) {
      const auto session = role == core::Role::cause ? run.cause_session : run.effect_session;
      store::Batch batch;
      batch.session_id = session;
      batch.events = chunk.events(role);
      for (const auto& s : chunk.clock_samples)
        if (s.node == role)
          batch.clock_samples.push_back(sim_clock_sample(s, session, sim_reference(config, role)));
      if (!batch.events.empty()) last = std::max(last, batch.events.back().time);
      store.append(batch);
      (role == core::Role::cause ? run.cause_events : run.effect_events) +=
          static_cast<std::int64_t>(batch.events.size());
    }
    total += static_cast<std::int64_t>(chunk.event_count());
    if (observer) observer(chunk, total);
  }
  store.end_session(run.cause_session, last);
  store.end_session(run.effect_session, last);
  whole.commit();
  return run;
}

namespace {

// One session of the full loop's board: begun, its trace (if any: else it is the LED's session, which
// like `m2mlat led` records no clock samples) and events and clock samples appended, ended one second
// after the run (the last clock sample).
std::int64_t record_board(store::Store& store, const sim::FullLoopRun& run, bool station, store::Session s,
                          const core::RateTrace* trace, std::span<const core::Event> events) {
  const auto clock = core::Clock::simulated;
  const std::int64_t offset = station ? run.station_offset_ns : run.vehicle_offset_ns;
  s.start = core::TimePoint::from_ns(clock, offset);
  const auto id = store.begin_session(s);
  store::Batch batch;
  batch.session_id = id;
  batch.events.assign(events.begin(), events.end());
  const auto samples = sim::board_clock_samples(run, station);
  for (const auto& b : samples) {
    if (trace == nullptr) break;
    store::ClockSample c;
    c.session_id = id;
    c.time = core::TimePoint::from_ns(clock, b.time_ns);
    c.source = "sim";
    c.max_error_ns = b.max_error_ns;
    c.est_error_ns = b.est_error_ns;
    c.synchronised = true;
    batch.clock_samples.push_back(c);
  }
  if (trace != nullptr)
    batch.rate_blocks = store::rate_block::split(id, "gyro", clock, trace->counts_per_deg_s, trace->samples);
  store.append(batch);
  store.end_session(id, core::TimePoint::from_ns(clock, samples.back().time_ns));
  return id;
}

core::Event full_loop_event(const std::string& node, const std::string& channel, core::Edge edge,
                            std::int64_t t_ns, std::uint32_t flags) {
  core::Event e;
  e.node = node;
  e.channel = channel;
  e.edge = edge;
  e.time = core::TimePoint::from_ns(core::Clock::simulated, t_ns);
  e.flags = core::kFlagSimulated | flags;
  return e;
}

}  // namespace

RecordedFullLoop record_full_loop(store::Store& store, const sim::FullLoopRun& run, FullLoopBoards boards,
                                  const std::string& label, const std::string& scenario) {
  if (run.config.single_board)
    throw core::Error(core::ErrorKind::usage,
                      "a single-board full loop has no gyroscopes: record it with `demo`, not into a store");
  const auto config = [&](const char* role) {
    return nlohmann::json{{"source", "sim"},
                          {"preset", "full_loop"},
                          {"seed", run.config.seed},
                          {"role", role},
                          {"baseline", run.config.baseline}};
  };
  const auto session = [&](const std::string& node, core::Role role, const nlohmann::json& json) {
    store::Session s;
    s.label = label;
    s.scenario = scenario;
    s.node = node;
    s.role = role;
    s.config_json = json.dump();
    return s;
  };
  RecordedFullLoop out;
  store::WholeWrite whole(store);  // the boards' sessions whole or not at all
  if (boards != FullLoopBoards::vehicle) {
    std::vector<core::Event> photo;
    for (const auto& m : run.manoeuvres)
      photo.push_back(full_loop_event("station", "photo", core::Edge::falling, m.photo_stamp_ns, 0));
    out.station_session = record_board(
        store, run, true, session("station", core::Role::cause, config("cause")), &run.station_trace, photo);
  }
  if (boards != FullLoopBoards::station) {
    out.vehicle_session = record_board(
        store, run, false, session("vehicle", core::Role::effect, config("effect")), &run.vehicle_trace, {});
    std::vector<core::Event> led;
    std::int64_t bound = 0;
    for (const auto& m : run.manoeuvres) {
      led.push_back(full_loop_event("vehicle", "led", core::Edge::rising, m.led_stamp_ns,
                                    core::kFlagCommanded | core::kFlagNoKernelSeqno));
      bound = std::max(bound, m.led_bound_ns);
    }
    auto json = config("effect");
    json["source"] = "led";
    json[store::kConfigLedBound] = bound;
    out.led_session =
        record_board(store, run, false, session("vehicle", core::Role::effect, json), nullptr, led);
  }
  whole.commit();
  return out;
}

}  // namespace m2mlat::capture
