// The streaming simulator: produces both nodes' edge events in time order, chunk by chunk, with
// their ground truth, in bounded memory (whatever the run's length, only the manoeuvres in flight
// are held). simulate.hpp collects a whole run into vectors; a simulated capture source wraps this.
//
// Each chunk continues the previous one: events keep their global indices (index = seqno - 1),
// and records that refer to events (passes, true pairs) appear in the chunk where the last of
// their events does. Same configuration and seed -> the same chunks, bit for bit, on every platform.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <queue>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/motion.hpp"
#include "m2mlat/sim/rig_config.hpp"
#include "m2mlat/sim/sensor.hpp"
#include "m2mlat/sim/truth.hpp"

namespace m2mlat::sim {

struct Chunk {
  std::vector<core::Event> cause_events;   // the operator board's edges, in time order
  std::vector<core::Event> effect_events;  // the vehicle board's edges, in time order
  std::vector<EventTruth> cause_truth;     // parallel to cause_events
  std::vector<EventTruth> effect_truth;    // parallel to effect_events
  std::int64_t cause_first_index = 0;      // global index of cause_events[0]
  std::int64_t effect_first_index = 0;     // global index of effect_events[0]
  std::vector<PassTruth> passes;           // passes whose events are all out, by index
  std::vector<TruePair> pairs;             // passes detected on both sides, by pass index
  std::vector<ManoeuvreTruth> manoeuvres;  // manoeuvres planned in this chunk
  std::vector<ClockSample> clock_samples;  // by time, cause before effect

  std::vector<core::Event>& events(core::Role role) {
    return role == core::Role::effect ? effect_events : cause_events;
  }
  const std::vector<core::Event>& events(core::Role role) const {
    return role == core::Role::effect ? effect_events : cause_events;
  }
  std::vector<EventTruth>& truth(core::Role role) {
    return role == core::Role::effect ? effect_truth : cause_truth;
  }
  const std::vector<EventTruth>& truth(core::Role role) const {
    return role == core::Role::effect ? effect_truth : cause_truth;
  }
  std::size_t event_count() const { return cause_events.size() + effect_events.size(); }
  void clear();  // keeps the capacity
};

class Generator {
 public:
  // Validates the configuration (core::Error(usage) on a bad field) and keeps its own copy.
  explicit Generator(const RigConfig& config);
  Generator(const Generator&) = delete;  // the planner and sensors refer to config_
  Generator& operator=(const Generator&) = delete;

  // Clears `chunk` and fills it with the next events of both nodes in true-time order, at most
  // `max_events` (both nodes together, at least 1), with the truth that became complete. Returns
  // false once the run is over and nothing more was produced.
  bool next(Chunk& chunk, std::size_t max_events = 65536);
  bool done() const { return done_; }
  const RigConfig& config() const { return config_; }
  // True time (ns since the epoch) where the run ends; known only once every manoeuvre is planned
  // (INT64_MAX before).
  std::int64_t end_ns() const { return end_ns_; }

 private:
  // An edge waiting for its turn, on one node.
  struct Pending {
    std::int64_t key_ns = 0;  // true time of the kernel's timestamp (edge + irq latency): the order
    std::uint64_t order = 0;  // creation order: breaks ties deterministically
    std::int64_t true_ns = 0;
    std::int64_t irq_ns = 0;
    EdgeKind kind = EdgeKind::pass;
    core::Edge edge = core::Edge::falling;
    std::int64_t manoeuvre = -1;
    std::int64_t pass = -1;
    std::int32_t magnet = -1;
    bool operator>(const Pending& o) const {
      return key_ns != o.key_ns ? key_ns > o.key_ns : order > o.order;
    }
  };
  using Queue = std::priority_queue<Pending, std::vector<Pending>, std::greater<Pending>>;
  // A pass whose events are not all out yet.
  struct OpenPass {
    PassTruth truth;
    int waiting = 0;  // detected sides not yet emitted
    std::int64_t cause_stamp_ns = 0;
    std::int64_t effect_stamp_ns = 0;
  };
  struct Side {
    core::Role role;
    SensorModel sensor;
    Queue queue;
    Pending spurious;  // the next spurious edge (key INT64_MAX: none)
    std::int64_t emitted = 0;
    std::int64_t last_key_ns = std::numeric_limits<std::int64_t>::min();  // of the last emitted edge
    Side(core::Role r, const SensorConfig& config, std::uint64_t seed) : role(r), sensor(config, seed, r) {}
  };

  void plan_manoeuvre(Chunk& chunk);
  void push_edges(Side& side, std::int64_t true_ns, std::int64_t manoeuvre, std::int64_t pass,
                  std::int32_t magnet, bool detected);
  void schedule_spurious(Side& side, std::int64_t after_ns);
  // SensorConfig::both_edges: a rising edge of the kind and pass of `like`, at true time `true_ns`,
  // stamped after `after_key_ns` (the falling edge it follows) and, where given, before
  // `before_key_ns` (the next falling edge of the same pulse train; none fits: no edge).
  void push_rising(Side& side, const Pending& like, std::int64_t true_ns, std::int64_t after_key_ns,
                   std::int64_t before_key_ns);
  void emit(Side& side, const Pending& edge, Chunk& chunk);
  void sample_clocks_until(std::int64_t true_ns, Chunk& chunk);  // samples at times <= true_ns
  void close_passes(Chunk& chunk);

  RigConfig config_;
  MotionPlanner planner_;
  ClockPair clocks_;
  Side cause_;
  Side effect_;
  ManoeuvrePlan plan_;  // reused
  std::vector<std::int64_t> bounce_scratch_;
  std::deque<OpenPass> open_;         // by pass index; front = oldest
  std::int64_t first_open_pass_ = 0;  // index of open_.front()
  std::int64_t passes_planned_ = 0;
  std::uint64_t order_ = 0;
  std::int64_t last_edge_ns_ = 0;  // latest true time of any planned edge
  std::int64_t end_ns_;
  std::int64_t next_sample_ns_;
  std::array<bool, 2> step_recorded_{};  // cause, effect: the configured clock step is in a chunk
  bool done_ = false;
};

}  // namespace m2mlat::sim
