// Which events of a campaign are causes and which are effects, and loading them.
//
// A campaign store holds sessions of several nodes, grouped by scenario. For one scenario the cause
// events are those of the cause channel (by default: the sessions whose role is cause), the effect
// events those of the effect channel; both as plain timestamp columns for the matcher.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

struct Selection {
  std::optional<core::ChannelRef> cause;                 // unset: the node of the scenario's cause sessions
  std::optional<core::ChannelRef> effect;                // unset: the node of the scenario's effect sessions
  std::optional<core::Edge> edge = core::Edge::falling;  // unset: both edges
  // > 0: drop the edges of `edge` that start no pulse this long (pairing/glitch_filter.hpp); needs
  // one edge kind and both kinds in the input.
  core::Duration min_pulse{0};
  // With min_pulse 0: drop those that start no pulse of kAutoMinPulse when both sides' lines hold both
  // kinds of edge (the default of every path, so that a store and its files count alike; a kernel log
  // holds one kind, and nothing is dropped).
  bool auto_min_pulse = true;
};

// A magnet's pass holds a Hall sensor's line for milliseconds (5 degrees at 400 deg/s: 12 ms), a
// burst of interference for microseconds.
inline constexpr core::Duration kAutoMinPulse{1'000'000};  // ns

// What the interference filter dropped (Selection::min_pulse), per side.
struct Glitches {
  core::Duration min_pulse{0};
  std::int64_t cause = 0, effect = 0;
};

// Events left out before pairing because their stamp is on no known clock (store::UnknownClock: a
// kernel log's outlier lines, and the lines stamped before its board's first synchronisation).
struct UnknownClockCounts {
  std::int64_t outlier = 0, before_sync = 0;
  std::int64_t total() const { return outlier + before_sync; }
};

// One scenario's two sides, ready for the matcher. `seq` says where each timestamp came from: the
// store's sequence number, or the index in an imported file's events. An empty `seq` beside a
// non-empty `t_ns` means "the position itself" (a file whose timestamps were already in time order):
// no column of 8 bytes an edge (80 MB at 10^7 edges) that would only count 0, 1, 2, ... Read it
// through source_id().
struct ScenarioInput {
  std::string scenario;
  core::ChannelRef cause_ref, effect_ref;
  core::Clock clock = core::Clock::realtime;
  store::Timestamps cause, effect;
  // What the seq numbers are: "seq" (store sequence numbers), "line" (line in a paired-results file)
  // or "index" (0-based position in an imported file's events).
  std::string id_kind = "seq";
  std::optional<Glitches> glitches;  // set when the interference filter ran
  UnknownClockCounts cause_unknown_clock, effect_unknown_clock;  // left out, not counted in the sides
};

// The source id of one side's timestamp at `index` (its position after sorting, as the matcher's
// indices count): seq[index], or the index itself when the side has no seq column.
inline std::int64_t source_id(const store::Timestamps& side, std::int64_t index) {
  return side.seq.empty() ? index : side.seq[static_cast<std::size_t>(index)];
}

// The node of one side of a scenario (`sessions`: the scenario's): the given one, or the single node
// whose sessions have `role`. Throws core::Error(data) naming the scenario when there is none or
// several (chains.hpp's store input picks its station and vehicle by the same rule).
std::string side_node(const std::vector<store::Session>& sessions, const std::string& scenario,
                      const std::optional<core::ChannelRef>& given, core::Role role);

// Scenario names in the order of their first session.
std::vector<std::string> scenarios(const store::Store& store);

// Loads one scenario. Throws core::Error(data) naming the scenario when a side has no session, when
// a node has several channels and none was chosen, when the two sides use different clocks, or when
// min_pulse is set and a side's channel holds one kind of edge only.
ScenarioInput load_scenario(const store::Store& store, const std::string& scenario,
                            const Selection& selection);

// One side as bare timestamps (ns on CLOCK_REALTIME, any order), e.g. from a kernel log.
struct SideInput {
  core::ChannelRef ref;
  std::vector<std::int64_t> t_ns;
};
// Sorts each side by time; a timestamp's id is its 0-based position in its input (seq left empty
// when the side was already in time order).
ScenarioInput from_timestamps(std::string scenario, SideInput cause, SideInput effect);

// The same from events in memory (e.g. imported files): filters by selection and sorts by time;
// the same errors as load_scenario, and a data error when the selection keeps no event of a side
// that has events (naming `names`' input, listing what it has, the nearest name and `advice`).
struct InputNames {
  std::string_view cause = "the cause input", effect = "the effect input";
  std::string_view advice;  // appended to the message of a selection that names nothing
};
ScenarioInput from_events(std::string scenario, std::span<const core::Event> causes,
                          std::span<const core::Event> effects, const Selection& selection,
                          const InputNames& names = {});

}  // namespace m2mlat::analysis
