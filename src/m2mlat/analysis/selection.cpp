// Loading cause and effect timestamps of a scenario from a store or from events in memory.
#include "m2mlat/analysis/selection.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <set>
#include <tuple>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/nearest.hpp"
#include "m2mlat/pairing/glitch_filter.hpp"

namespace m2mlat::analysis {

namespace {

constexpr std::array kClocks{core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime,
                             core::Clock::simulated};

// Sorts the two parallel columns by time (stable, so equal times keep their seq order). A side without
// a seq column (ids = positions) gets one first: sorting moves the timestamps away from their positions.
void sort_by_time(store::Timestamps& t) {
  if (std::is_sorted(t.t_ns.begin(), t.t_ns.end())) return;
  if (t.seq.empty()) {
    t.seq.resize(t.t_ns.size());
    std::iota(t.seq.begin(), t.seq.end(), std::int64_t{0});
  }
  std::vector<std::size_t> order(t.t_ns.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return t.t_ns[a] < t.t_ns[b]; });
  store::Timestamps sorted{t.clock, {}, {}};
  sorted.seq.reserve(order.size());
  sorted.t_ns.reserve(order.size());
  for (auto k : order) {
    sorted.seq.push_back(t.seq[k]);
    sorted.t_ns.push_back(t.t_ns[k]);
  }
  t = std::move(sorted);
}

// What an input holds of one channel: its events by edge.
struct Present {
  std::string ref;  // node/channel
  std::int64_t edges[2] = {0, 0};  // by core::Edge
};
void count_present(std::vector<Present>& present, const std::string& ref, core::Edge edge, std::int64_t n) {
  auto it = std::find_if(present.begin(), present.end(), [&](const Present& p) { return p.ref == ref; });
  if (it == present.end()) it = present.insert(present.end(), Present{ref});
  it->edges[static_cast<int>(edge)] += n;
}

// A selection that names nothing: data error listing what the input has and the nearest name.
[[noreturn]] void throw_nothing_selected(std::string_view where, std::string_view side, const core::ChannelRef& want,
                                         std::optional<core::Edge> edge, const std::vector<Present>& present,
                                         std::string_view advice = {}) {
  std::vector<std::string> names, listed;
  for (const auto& p : present) {
    names.push_back(p.ref);
    std::vector<std::string> counts;
    for (const auto e : {core::Edge::falling, core::Edge::rising})
      if (p.edges[static_cast<int>(e)] != 0) counts.push_back(fmt::format("{} {}", p.edges[static_cast<int>(e)], core::to_string(e)));
    listed.push_back(fmt::format("{} ({})", p.ref, fmt::join(counts, ", ")));
  }
  const std::string wanted = want.channel.empty() ? want.node : core::to_string(want);
  const std::string edges = edge ? fmt::format(", {} edges", core::to_string(*edge)) : std::string{};
  throw core::Error(core::ErrorKind::data,
                    fmt::format("{}: no {} events of {}{}; it has {}{}{}", where, side, wanted, edges,
                                listed.empty() ? std::string("none") : fmt::format("{}", fmt::join(listed, ", ")),
                                core::did_you_mean(wanted, names), advice));
}

// Loads one side: every session of the scenario on `node`, the chosen channel (or the node's only
// channel) and edge, on whichever single clock they use.
store::Timestamps load_side(const store::Store& store, const std::vector<store::Session>& sessions,
                            const std::string& scenario, core::ChannelRef& ref,
                            std::optional<core::Edge> edge) {
  if (ref.channel.empty()) {
    std::set<std::string> channels;
    for (const auto& s : sessions)
      if (s.node == ref.node)
        for (auto& c : store.channels(s.id)) channels.insert(std::move(c));
    if (channels.size() > 1)
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("node '{}' has several channels in scenario '{}' ({}): choose one as {}/<channel>",
                      ref.node, scenario, fmt::join(channels, ", "), ref.node));
    if (!channels.empty()) ref.channel = *channels.begin();
  }
  store::Timestamps side;
  std::optional<core::Clock> seen;
  for (const auto& s : sessions) {
    if (s.node != ref.node) continue;
    store::EventFilter filter;
    filter.session_id = s.id;
    filter.channel = ref.channel;
    filter.edge = edge;
    for (auto clock : kClocks) {
      auto part =
          store.timestamps(core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::min()),
                           core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::max()), filter);
      if (part.t_ns.empty()) continue;
      if (seen && *seen != clock)
        throw core::Error(
            core::ErrorKind::data,
            fmt::format("{} has events on two clocks ({} and {}) in scenario '{}'", core::to_string(ref),
                        core::to_string(*seen), core::to_string(clock), scenario));
      seen = clock;
      side.seq.insert(side.seq.end(), part.seq.begin(), part.seq.end());
      side.t_ns.insert(side.t_ns.end(), part.t_ns.begin(), part.t_ns.end());
    }
  }
  side.clock = seen.value_or(core::Clock::realtime);
  sort_by_time(side);
  return side;
}

core::Edge opposite(core::Edge edge) {
  return edge == core::Edge::falling ? core::Edge::rising : core::Edge::falling;
}

// Drops from `side` (edges of `edge`, sorted by time) those that start no pulse of `min_pulse`, given
// the line's other edges `idle_ns` (sorted); returns how many. A side whose line has no other edges is
// refused: without them no pulse has a width.
std::int64_t drop_glitches(store::Timestamps& side, std::span<const std::int64_t> idle_ns, core::Edge edge,
                           core::Duration min_pulse, const core::ChannelRef& ref) {
  if (side.t_ns.empty()) return 0;
  if (idle_ns.empty())
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("--min-pulse needs both edges of a line, and {} has {} edges only (record it "
                    "with --edges both --refractory 0)",
                    core::to_string(ref), core::to_string(edge)));
  const auto drop = pairing::glitches(side.t_ns, idle_ns, min_pulse);
  if (drop.empty()) return 0;
  if (side.seq.empty()) {  // ids were positions: keep them as they were before the drop
    side.seq.resize(side.t_ns.size());
    std::iota(side.seq.begin(), side.seq.end(), std::int64_t{0});
  }
  std::size_t out = 0, next_drop = 0;
  for (std::size_t k = 0; k < side.t_ns.size(); ++k) {
    if (next_drop < drop.size() && static_cast<std::size_t>(drop[next_drop]) == k) {
      ++next_drop;
      continue;
    }
    side.t_ns[out] = side.t_ns[k], side.seq[out] = side.seq[k];
    ++out;
  }
  side.t_ns.resize(out), side.seq.resize(out);
  return static_cast<std::int64_t>(drop.size());
}

// The interference filter on both sides, given each line's other edges (sorted): with the selection's
// min_pulse, or kAutoMinPulse when it asks for the automatic filter and both lines hold both edges.
void filter_glitches(ScenarioInput& input, std::span<const std::int64_t> cause_idle,
                     std::span<const std::int64_t> effect_idle, const Selection& selection) {
  core::Duration min_pulse = selection.min_pulse;
  if (min_pulse.count() == 0) {
    if (!selection.auto_min_pulse || cause_idle.empty() || effect_idle.empty()) return;
    min_pulse = kAutoMinPulse;
  }
  Glitches g{min_pulse};
  g.cause = drop_glitches(input.cause, cause_idle, *selection.edge, min_pulse, input.cause_ref);
  g.effect = drop_glitches(input.effect, effect_idle, *selection.edge, min_pulse, input.effect_ref);
  input.glitches = g;
}

// Selection::min_pulse needs one kind of edge to pair: the other kind is the pulses' ends.
void check_min_pulse(const Selection& selection) {
  if (selection.min_pulse.count() > 0 && !selection.edge)
    throw core::Error(core::ErrorKind::usage,
                      "--min-pulse needs the edges to pair: --edge falling or rising");
}

void check_clocks(const ScenarioInput& input) {
  if (!input.cause.t_ns.empty() && !input.effect.t_ns.empty() && input.cause.clock != input.effect.clock)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("scenario '{}': cause {} is on {} but effect {} is on {}; only timestamps of one "
                    "clock can be subtracted",
                    input.scenario, core::to_string(input.cause_ref), core::to_string(input.cause.clock),
                    core::to_string(input.effect_ref), core::to_string(input.effect.clock)));
}

}  // namespace

std::string side_node(const std::vector<store::Session>& sessions, const std::string& scenario,
                      const std::optional<core::ChannelRef>& given, core::Role role) {
  const auto side = core::to_string(role);
  std::set<std::string> nodes;
  for (const auto& s : sessions)
    if (given ? s.node == given->node : s.role == role) nodes.insert(s.node);
  if (nodes.empty()) {
    std::vector<std::string> all;
    for (const auto& s : sessions)
      if (std::find(all.begin(), all.end(), s.node) == all.end()) all.push_back(s.node);
    throw core::Error(core::ErrorKind::data,
                      given ? fmt::format("scenario '{}' has no session of node '{}'; its nodes are {}{}", scenario,
                                          given->node, fmt::join(all, ", "), core::did_you_mean(given->node, all))
                            : fmt::format("scenario '{}' has no {} session (record or import one with role {})",
                                          scenario, side, side));
  }
  if (nodes.size() > 1)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("scenario '{}' has several {} nodes ({}): choose one with --{} node/channel", scenario,
                    side, fmt::join(nodes, ", "), side));
  return *nodes.begin();
}

std::vector<std::string> scenarios(const store::Store& store) {
  std::vector<std::string> names;
  for (const auto& s : store.sessions())
    if (std::find(names.begin(), names.end(), s.scenario) == names.end()) names.push_back(s.scenario);
  return names;
}

namespace {

// An empty side of a store's scenario whose node has events of another channel or edge: the
// selection named nothing that exists (a node without any events is left alone: nothing to choose).
void check_something_selected(const store::Store& store, const std::vector<store::Session>& sessions,
                              const std::string& scenario, const core::ChannelRef& ref,
                              std::optional<core::Edge> edge, std::string_view side) {
  std::vector<Present> present;
  bool node_has_events = false;
  for (const auto& s : sessions)
    for (const auto& channel : store.channels(s.id))
      for (const auto e : {core::Edge::falling, core::Edge::rising}) {
        store::EventFilter filter;
        filter.session_id = s.id;
        filter.channel = channel;
        filter.edge = e;
        std::int64_t n = 0;
        for (auto clock : kClocks)
          n += static_cast<std::int64_t>(
              store.timestamps(core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::min()),
                               core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::max()), filter)
                  .t_ns.size());
        if (n == 0) continue;
        count_present(present, s.node + "/" + channel, e, n);
        node_has_events = node_has_events || s.node == ref.node;
      }
  if (node_has_events)
    throw_nothing_selected(fmt::format("{}: scenario '{}'", store.path(), scenario), side, ref, edge, present,
                           fmt::format(": choose with --{} node/channel or --edge", side));
}

}  // namespace

ScenarioInput load_scenario(const store::Store& store, const std::string& scenario,
                            const Selection& selection) {
  std::vector<store::Session> sessions;
  for (auto& s : store.sessions())
    if (s.scenario == scenario) sessions.push_back(std::move(s));
  if (sessions.empty()) {
    const auto names = scenarios(store);
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: no scenario '{}'; it has {}{}", store.path(), scenario,
                                  names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", ")),
                                  core::did_you_mean(scenario, names)));
  }

  ScenarioInput input;
  input.scenario = scenario;
  input.cause_ref = {side_node(sessions, scenario, selection.cause, core::Role::cause),
                     selection.cause ? selection.cause->channel : ""};
  input.effect_ref = {side_node(sessions, scenario, selection.effect, core::Role::effect),
                      selection.effect ? selection.effect->channel : ""};
  check_min_pulse(selection);
  input.cause = load_side(store, sessions, scenario, input.cause_ref, selection.edge);
  input.effect = load_side(store, sessions, scenario, input.effect_ref, selection.edge);
  for (auto [side, ref, name] : {std::tuple{&input.cause, &input.cause_ref, "cause"}, std::tuple{&input.effect, &input.effect_ref, "effect"}})
    if (side->t_ns.empty()) check_something_selected(store, sessions, scenario, *ref, selection.edge, name);
  if (selection.edge && (selection.min_pulse.count() > 0 || selection.auto_min_pulse)) {
    const auto other = opposite(*selection.edge);
    const auto cause_idle = load_side(store, sessions, scenario, input.cause_ref, other).t_ns;
    const auto effect_idle = load_side(store, sessions, scenario, input.effect_ref, other).t_ns;
    filter_glitches(input, cause_idle, effect_idle, selection);
  }
  input.clock = input.cause.clock;
  check_clocks(input);
  return input;
}

ScenarioInput from_timestamps(std::string scenario, SideInput cause, SideInput effect) {
  ScenarioInput input;
  input.scenario = std::move(scenario);
  input.id_kind = "index";
  input.clock = core::Clock::realtime;
  auto take = [](SideInput& side, core::ChannelRef& ref, store::Timestamps& out) {
    ref = std::move(side.ref);
    out.clock = core::Clock::realtime;
    out.t_ns = std::move(side.t_ns);  // seq stays empty: ids are positions, unless sorting moves them
    sort_by_time(out);
  };
  take(cause, input.cause_ref, input.cause);
  take(effect, input.effect_ref, input.effect);
  return input;
}

ScenarioInput from_events(std::string scenario, std::span<const core::Event> causes,
                          std::span<const core::Event> effects, const Selection& selection, const InputNames& names) {
  ScenarioInput input;
  input.scenario = std::move(scenario);
  input.id_kind = "index";
  check_min_pulse(selection);
  const bool filter = selection.edge && (selection.min_pulse.count() > 0 || selection.auto_min_pulse);
  // Takes one side's events of the selected edge into `out`, and returns its line's other edges
  // (sorted) for the interference filter.
  auto take = [&](std::span<const core::Event> events, const std::optional<core::ChannelRef>& want,
                  core::ChannelRef& ref, store::Timestamps& out, const char* side,
                  std::string_view where) -> std::vector<std::int64_t> {
    std::optional<core::Clock> seen;
    std::vector<std::size_t> others;  // the other kind of edge, for the interference filter
    for (std::size_t k = 0; k < events.size(); ++k) {
      const auto& e = events[k];
      if (want && (e.node != want->node || (!want->channel.empty() && e.channel != want->channel))) continue;
      if (selection.edge && e.edge != *selection.edge) {
        if (filter) others.push_back(k);
        continue;
      }
      if (ref.node.empty()) ref = {e.node, e.channel};
      if ((!want || want->channel.empty()) && (e.node != ref.node || e.channel != ref.channel))
        throw core::Error(
            core::ErrorKind::data,
            fmt::format("the {} input has events of {} and {}/{}: choose one with --{} node/channel", side,
                        core::to_string(ref), e.node, e.channel, side));
      if (seen && *seen != e.time.clock())
        throw core::Error(core::ErrorKind::data,
                          fmt::format("the {} input mixes {} and {} timestamps", side, core::to_string(*seen),
                                      core::to_string(e.time.clock())));
      seen = e.time.clock();
      out.seq.push_back(static_cast<std::int64_t>(k));
      out.t_ns.push_back(e.time.ns());
    }
    if (want && ref.node.empty()) ref = *want;
    if (out.t_ns.empty() && !events.empty()) {
      std::vector<Present> present;
      for (const auto& e : events) count_present(present, e.node + "/" + e.channel, e.edge, 1);
      throw_nothing_selected(where, side, want.value_or(ref), selection.edge, present, names.advice);
    }
    out.clock = seen.value_or(core::Clock::realtime);
    sort_by_time(out);
    std::vector<std::int64_t> idle_ns;  // the same line's other edges, sorted
    for (auto k : others)
      if (events[k].node == ref.node && events[k].channel == ref.channel)
        idle_ns.push_back(events[k].time.ns());
    std::sort(idle_ns.begin(), idle_ns.end());
    return idle_ns;
  };
  const auto cause_idle = take(causes, selection.cause, input.cause_ref, input.cause, "cause", names.cause);
  const auto effect_idle = take(effects, selection.effect, input.effect_ref, input.effect, "effect", names.effect);
  if (filter) filter_glitches(input, cause_idle, effect_idle, selection);
  input.clock = input.cause.clock;
  check_clocks(input);
  return input;
}

}  // namespace m2mlat::analysis
