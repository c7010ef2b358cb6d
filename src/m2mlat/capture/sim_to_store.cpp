// Simulated run -> store, chunk by chunk; one transaction per node per chunk.
#include "m2mlat/capture/sim_to_store.hpp"

#include <nlohmann/json.hpp>

#include "m2mlat/capture/sim_source.hpp"

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
  return run;
}

}  // namespace m2mlat::capture
