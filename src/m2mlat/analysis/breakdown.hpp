// Where an M2M event's time goes: each pair (cause onset on the operator's board, effect onset on
// the vehicle's) is joined to the markers between its cause and its effect by a StageRule
// (stage_rule.hpp), giving a row of stage durations that adds up to the pair's M2M exactly; events
// whose chain is incomplete are kept with the stage and the reason (docs/breakdown.md).
//
// Markers come from anywhere (m2mlat-markers/1 files, the simulator; the store's markers later): the
// entry point takes them as values. Times are int64 ns on CLOCK_REALTIME, the events' clock.
#pragma once

#include <compare>
#include <cstdint>
#include <map>
#include <tuple>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/stage_rule.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/markers/marker.hpp"
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::analysis {

// The markers, indexed for the selectors: per node and name by time, and per node, name and key.
class MarkerIndex {
 public:
  explicit MarkerIndex(std::span<const markers::Marker> markers);
  std::size_t size() const { return size_; }

  struct Stamp {
    std::int64_t ns = 0;
    std::uint32_t marker = 0;  // position in the markers given
    friend auto operator<=>(const Stamp&, const Stamp&) = default;  // by time, then position
  };
  // Sorted by time; empty when no such marker.
  std::span<const Stamp> of(const std::string& node, const std::string& name) const;
  std::span<const Stamp> of(const std::string& node, const std::string& name, const std::string& key) const;
  const markers::Marker& marker(std::uint32_t i) const { return markers_[i]; }

 private:
  std::span<const markers::Marker> markers_;
  std::map<std::pair<std::string, std::string>, std::vector<Stamp>> by_name_;
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<Stamp>> by_key_;
  std::size_t size_ = 0;
};

// Why an event's chain stops. Names are written in files: never rename.
enum class StageGap : std::uint8_t {
  none,          // complete
  missing,       // no marker the selector accepts
  out_of_order,  // the marker found lies before the previous stage's end
  after_effect,  // the marker found lies after the effect
};
std::string_view to_string(StageGap gap);

// One event's stages.
struct EventStages {
  std::size_t pair = 0;       // index into the scenario's match.pairs
  std::int64_t cause_id = 0;  // the cause event's store seq or file index
  core::TimePoint cause_time, effect_time;
  std::int64_t m2m_ns = 0;  // effect - cause
  // Complete: one duration a stage (ns), adding up to m2m_ns. Incomplete: the stages before the gap.
  std::vector<std::int64_t> stage_ns;
  StageGap gap = StageGap::none;
  std::size_t gap_stage = 0;  // the stage whose end was not found (gap != none)
  std::string detail;         // what was looked for, e.g. "no vehicle:receive with key 12"
  bool complete() const { return gap == StageGap::none; }
};

// One stage over the complete events of a scenario (ns).
struct StageStats {
  std::string name;
  std::string selector;  // as written in the rule
  double median_ns = 0, q1_ns = 0, q3_ns = 0, mean_ns = 0;
  std::int64_t min_ns = 0, max_ns = 0;
  // The stage's share of the total: sum of this stage over the complete events / sum of their M2M
  // (= mean stage / mean M2M), so the shares add up to 1; NaN without complete events.
  double share = 0;
};

// Incomplete chains counted by the stage where they stop and why.
struct GapCount {
  std::string stage;
  StageGap gap = StageGap::missing;
  std::size_t count = 0;
};

struct Breakdown {
  std::vector<StageStats> stages;  // in the rule's order
  std::vector<EventStages> events;  // every pair in the statistics, complete or not, in pair order
  std::size_t complete = 0, incomplete = 0;
  double m2m_median_ns = 0, m2m_mean_ns = 0;  // over the complete events (NaN without one)
  std::vector<GapCount> gaps;  // in the rule's stage order, then by reason
};

// The stages of one event: its cause and effect edges' times (ns on `clock`, the match's); throws
// core::Error(data) when `clock` is not CLOCK_REALTIME.
EventStages event_stages(std::int64_t cause_ns, std::int64_t effect_ns, core::Clock clock,
                         const StageRule& rule, const MarkerIndex& index);

// The breakdown of the given events (event i: its edges at `cause_ns[i]` and `effect_ns[i]` on
// `clock`, its cause id `cause_ids[i]` and its pair's position `positions[i]` in the scenario's
// match): every event, the per-stage statistics over the complete ones.
Breakdown break_down(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                     core::Clock clock, std::span<const std::size_t> positions,
                     std::span<const std::int64_t> cause_ids, const StageRule& rule,
                     const MarkerIndex& index);
// The statistics of events already joined (event_stages, with their pair and cause_id set), kept in
// the order given: what break_down does after the joins, and the live view over joins it keeps.
Breakdown summarize_stages(std::vector<EventStages> events, const StageRule& rule);

}  // namespace m2mlat::analysis
