// The chains' input from stores (see store_chains.hpp).
#include "m2mlat/analysis/store_chains.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::analysis {

namespace {

constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
constexpr std::array kChainClocks{core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime,
                                  core::Clock::simulated};

// One board's part of a scenario: the store holding it and the scenario's sessions there.
struct BoardSessions {
  const store::Store& store;
  std::vector<store::Session> sessions;      // the scenario's, in id order
  std::vector<store::RateChannel> channels;  // the rate channels of those sessions
};

BoardSessions board_sessions(const store::Store& store, const std::string& scenario) {
  BoardSessions b{store, {}, {}};
  std::set<std::int64_t> ids;
  for (auto& s : store.sessions())
    if (s.scenario == scenario) {
      ids.insert(s.id);
      b.sessions.push_back(std::move(s));
    }
  if (b.sessions.empty())
    throw core::Error(core::ErrorKind::data, fmt::format("{}: no scenario '{}'", store.path(), scenario));
  for (auto& c : store.rate_channels())
    if (ids.contains(c.session_id)) b.channels.push_back(std::move(c));
  return b;
}

std::string traces_text(const BoardSessions& b) {
  std::set<std::string> refs;
  for (const auto& c : b.channels) refs.insert(c.node + "/" + c.channel);
  return refs.empty() ? std::string("none") : fmt::format("{}", fmt::join(refs, ", "));
}

// The node of one side among the sessions with a trace: the given one, the only one (`any_role`: a
// board's own store), or by role as selection.hpp's side_node chooses.
std::string trace_node(const BoardSessions& b, const std::string& scenario,
                       const std::optional<core::ChannelRef>& given, core::Role role, bool any_role) {
  const char* board = role == core::Role::cause ? "station" : "vehicle";
  std::set<std::int64_t> with_trace;
  std::set<std::string> nodes;
  for (const auto& c : b.channels) {
    with_trace.insert(c.session_id);
    nodes.insert(c.node);
  }
  std::vector<store::Session> traced;
  for (const auto& s : b.sessions)
    if (with_trace.contains(s.id)) traced.push_back(s);
  if (given) {
    if (!nodes.contains(given->node))
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: scenario '{}': node '{}' ({}) has no gyroscope trace (traces: {}); "
                                    "record it with `record --gyro`",
                                    b.store.path(), scenario, given->node, board, traces_text(b)));
    return given->node;
  }
  if (any_role && nodes.size() == 1) return *nodes.begin();
  const bool found = std::any_of(traced.begin(), traced.end(), [&](const auto& s) { return s.role == role; });
  if (!found)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: scenario '{}' has no {} ({} node) with a gyroscope trace (traces: {}); record it "
                    "with `record --gyro --role {}`, or name it with --{} node",
                    b.store.path(), scenario, board, core::to_string(role), traces_text(b),
                    core::to_string(role), core::to_string(role)));
  return side_node(traced, scenario, std::nullopt, role);
}

// The node's rate channel: the given one, or its only one.
std::string trace_channel(const BoardSessions& b, const std::string& scenario, const std::string& node,
                          const std::optional<core::ChannelRef>& given) {
  std::set<std::string> channels;
  for (const auto& c : b.channels)
    if (c.node == node) channels.insert(c.channel);
  if (given && !given->channel.empty()) {
    if (!channels.contains(given->channel))
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("{}: scenario '{}': node '{}' has no gyroscope trace on channel '{}' "
                      "(its traces: {})",
                      b.store.path(), scenario, node, given->channel, fmt::join(channels, ", ")));
    return given->channel;
  }
  if (channels.size() > 1)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: scenario '{}': node '{}' has several gyroscope traces ({}): choose one "
                    "as {}/<channel>",
                    b.store.path(), scenario, node, fmt::join(channels, ", "), node));
  return *channels.begin();
}

// Every session's trace of the node and channel, joined in time order (each session's last `window`
// only, when set).
core::RateTrace node_trace(const BoardSessions& b, const std::string& scenario, const std::string& node,
                           const std::string& channel, const std::optional<core::Duration>& window) {
  core::RateTrace trace;
  bool first = true;
  for (const auto& c : b.channels) {
    if (c.node != node || c.channel != channel) continue;
    auto part = window ? b.store.rate_trace_tail(c.session_id, channel, window->count())
                       : b.store.rate_trace(c.session_id, channel);
    if (!first && (part.clock != trace.clock || part.counts_per_deg_s != trace.counts_per_deg_s))
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("{}: scenario '{}': the traces of {}/{} disagree on the clock or the scale "
                      "(session {})",
                      b.store.path(), scenario, node, channel, c.session_id));
    if (first) {
      trace.clock = part.clock;
      trace.counts_per_deg_s = part.counts_per_deg_s;
      first = false;
    }
    trace.samples.insert(trace.samples.end(), part.samples.begin(), part.samples.end());
  }
  std::stable_sort(trace.samples.begin(), trace.samples.end(),
                   [](const auto& x, const auto& y) { return x.time_ns < y.time_ns; });
  return trace;
}

// The node's events of one channel (and edge) in the scenario, on `clock`; refused on another clock.
std::vector<store::StoredEvent> node_events(const BoardSessions& b, const std::string& scenario,
                                            const std::string& node, const std::string& channel,
                                            std::optional<core::Edge> edge, core::Clock clock,
                                            std::int64_t from_ns) {
  std::vector<store::StoredEvent> out;
  for (const auto& s : b.sessions) {
    if (s.node != node) continue;
    store::EventFilter filter;
    filter.session_id = s.id;
    filter.channel = channel;
    filter.edge = edge;
    for (auto on : kChainClocks) {
      auto part = b.store.events_in_time(
          core::TimePoint::from_ns(on, on == clock ? from_ns : kMin),
          core::TimePoint::from_ns(on, std::numeric_limits<std::int64_t>::max()), filter);
      if (part.empty()) continue;
      if (on != clock)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: scenario '{}': {}/{} is on {} but the gyroscope traces are on {}",
                                      b.store.path(), scenario, node, channel, core::to_string(on),
                                      core::to_string(clock)));
      out.insert(out.end(), part.begin(), part.end());
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& x, const auto& y) { return x.event.time.ns() < y.event.time.ns(); });
  return out;
}

ClockTrack node_clock(const BoardSessions& b, const std::string& node, core::Clock clock) {
  std::vector<store::ClockSample> samples;
  for (const auto& s : b.sessions)
    if (s.node == node)
      for (auto& c : b.store.clock_samples(s.id)) samples.push_back(std::move(c));
  auto track = make_clock_track(std::move(samples), clock);
  track.node = node;
  return track;
}

// The largest half-width an LED session recorded, ns; nullopt if its configuration has none.
std::optional<std::int64_t> led_bound(const store::Session& session) {
  const auto config = nlohmann::json::parse(session.config_json, nullptr, false);
  if (!config.is_object()) return std::nullopt;
  const auto it = config.find(store::kConfigLedBound);
  if (it == config.end() || !it->is_number_integer() || it->get<std::int64_t>() < 0) return std::nullopt;
  return it->get<std::int64_t>();
}

std::set<std::string> event_channels(const BoardSessions& b, const std::string& node) {
  std::set<std::string> out;
  for (const auto& s : b.sessions)
    if (s.node == node)
      for (auto& c : b.store.channels(s.id)) out.insert(std::move(c));
  return out;
}

StoreChainInput build_input(const BoardSessions& st, const BoardSessions& ve, const std::string& scenario,
                            const ChainSelection& sel, bool two_stores) {
  StoreChainInput out;
  out.station_node = trace_node(st, scenario, sel.station, core::Role::cause, two_stores);
  out.vehicle_node = trace_node(ve, scenario, sel.vehicle, core::Role::effect, two_stores);
  if (!two_stores && out.station_node == out.vehicle_node)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: scenario '{}': station and vehicle are the same node '{}'",
                                  st.store.path(), scenario, out.station_node));
  out.station_channel = trace_channel(st, scenario, out.station_node, sel.station);
  out.vehicle_channel = trace_channel(ve, scenario, out.vehicle_node, sel.vehicle);
  auto& in = out.input;
  in.station_trace = node_trace(st, scenario, out.station_node, out.station_channel, sel.window);
  in.vehicle_trace = node_trace(ve, scenario, out.vehicle_node, out.vehicle_channel, sel.window);
  const auto clock = in.station_trace.clock;
  std::int64_t from_ns = kMin;
  if (sel.window) {
    // The window: from the newest stamp of either trace back; older samples of either trace are cut.
    std::int64_t newest = kMin;
    for (const auto* t : {&in.station_trace, &in.vehicle_trace})
      if (!t->samples.empty()) newest = std::max(newest, t->samples.back().time_ns);
    from_ns = newest - sel.window->count();
    out.window_start_ns = from_ns;
    for (auto* t : {&in.station_trace, &in.vehicle_trace})
      std::erase_if(t->samples, [&](const core::RateSample& x) { return x.time_ns < from_ns; });
  }
  if (in.vehicle_trace.clock != clock)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: scenario '{}': the station's trace is on {}, the vehicle's on {}", ve.store.path(),
                    scenario, core::to_string(clock), core::to_string(in.vehicle_trace.clock)));

  // The LED's writes: rising edges m2mlat commanded, each with its session's bound.
  std::set<std::int64_t> assumed;
  for (const auto& e :
       node_events(ve, scenario, out.vehicle_node, sel.led_channel, core::Edge::rising, clock, from_ns)) {
    if ((e.event.flags & core::kFlagCommanded) == 0) continue;
    const auto session = std::find_if(ve.sessions.begin(), ve.sessions.end(),
                                      [&](const auto& s) { return s.id == e.session_id; });
    auto bound = led_bound(*session);
    if (!bound) {
      assumed.insert(e.session_id);
      bound = sel.default_led_bound.count();
    }
    in.led.push_back({e.event.time.ns(), *bound});
  }
  for (const auto id : assumed)
    out.warnings.push_back(fmt::format(
        "{}: scenario '{}': session {} ({}/{}) recorded no LED write bound ({}): {} assumed for each write",
        ve.store.path(), scenario, id, out.vehicle_node, sel.led_channel, store::kConfigLedBound,
        core::format_duration(sel.default_led_bound)));
  for (const auto& e :
       node_events(st, scenario, out.station_node, sel.photo_channel, sel.photo_edge, clock, from_ns))
    in.photo_ns.push_back(e.event.time.ns());
  if (!in.led.empty() && in.photo_ns.empty()) {
    const auto channels = event_channels(st, out.station_node);
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: scenario '{}': {} LED writes on {}/{} but no photo edges on {}/{} (its "
                    "channels: {}); name the phototransistor's channel with --photo-channel",
                    st.store.path(), scenario, in.led.size(), out.vehicle_node, sel.led_channel,
                    out.station_node, sel.photo_channel,
                    channels.empty() ? std::string("none") : fmt::format("{}", fmt::join(channels, ", "))));
  }
  if (in.led.empty())
    out.warnings.push_back(
        fmt::format("{}: scenario '{}': no LED writes on {}/{}: M2M only (G2G and E2E missing)",
                    ve.store.path(), scenario, out.vehicle_node, sel.led_channel));
  in.station_clock = node_clock(st, out.station_node, clock);
  in.vehicle_clock = node_clock(ve, out.vehicle_node, clock);
  return out;
}

}  // namespace

bool has_rate_traces(const store::Store& store, const std::string& scenario) {
  std::set<std::int64_t> ids;
  for (const auto& s : store.sessions())
    if (s.scenario == scenario) ids.insert(s.id);
  const auto channels = store.rate_channels();
  return std::any_of(channels.begin(), channels.end(),
                     [&](const auto& c) { return ids.contains(c.session_id); });
}

StoreChainInput chain_input(const store::Store& store, const std::string& scenario,
                            const ChainSelection& selection) {
  const auto board = board_sessions(store, scenario);
  return build_input(board, board, scenario, selection, false);
}

StoreChainInput chain_input(const store::Store& station, const store::Store& vehicle,
                            const std::string& scenario, const ChainSelection& selection) {
  return build_input(board_sessions(station, scenario), board_sessions(vehicle, scenario), scenario,
                     selection, true);
}

std::vector<FullLoopResult> store_chains(const store::Store& store, const std::vector<std::string>& only,
                                         const ChainSelection& selection, const ChainOptions& options,
                                         const stats::SummaryOptions& summary,
                                         std::vector<std::string>& warnings) {
  std::vector<FullLoopResult> out;
  for (const auto& name : scenarios(store)) {
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    if (!has_rate_traces(store, name)) continue;
    auto input = chain_input(store, name, selection);
    warnings.insert(warnings.end(), input.warnings.begin(), input.warnings.end());
    auto chains = build_chains(input.input, options, summary, name);
    chains.loop.file = fmt::format("{}: chains ({})", store.path(), chains.detector);
    out.push_back(std::move(chains.loop));
  }
  return out;
}

std::vector<FullLoopResult> take_chain_stores(PipelineInputs& inputs, const ChainSelection& selection,
                                              const ChainOptions& options,
                                              const stats::SummaryOptions& summary,
                                              std::vector<std::string>& warnings) {
  store::Options read;
  read.read_only = true;
  const auto selected = [&](const store::Store& store) {
    std::vector<std::string> names;
    for (const auto& name : scenarios(store))
      if (inputs.scenarios.empty() ||
          std::find(inputs.scenarios.begin(), inputs.scenarios.end(), name) != inputs.scenarios.end())
        names.push_back(name);
    return names;
  };
  std::vector<FullLoopResult> out;
  if (!inputs.cause_file.empty() && !inputs.effect_file.empty() &&
      store::is_sqlite_database(inputs.cause_file) && store::is_sqlite_database(inputs.effect_file)) {
    const auto station = store::Store::open(inputs.cause_file, read);
    const auto vehicle = store::Store::open(inputs.effect_file, read);
    bool any = false;
    for (const auto& name : selected(station)) {
      if (!has_rate_traces(station, name)) continue;
      any = true;
      auto input = chain_input(station, vehicle, name, selection);
      warnings.insert(warnings.end(), input.warnings.begin(), input.warnings.end());
      auto chains = build_chains(input.input, options, summary, name);
      chains.loop.file =
          fmt::format("{} + {}: chains ({})", inputs.cause_file, inputs.effect_file, chains.detector);
      out.push_back(std::move(chains.loop));
    }
    if (any) {
      inputs.cause_file.clear();
      inputs.effect_file.clear();
    }
  }
  std::vector<std::string> rest;
  for (auto& path : inputs.inputs) {
    if (path == "-" || !store::is_sqlite_database(path)) {
      rest.push_back(std::move(path));
      continue;
    }
    const auto store = store::Store::open(path, read);
    const auto names = selected(store);
    std::vector<std::string> traced;
    for (const auto& name : names)
      if (has_rate_traces(store, name)) traced.push_back(name);
    if (traced.empty()) {
      rest.push_back(std::move(path));
      continue;
    }
    for (auto& c : store_chains(store, traced, selection, options, summary, warnings))
      out.push_back(std::move(c));
    if (traced.size() == names.size()) continue;  // nothing left for the pipeline
    for (const auto& name : traced) inputs.skip.emplace_back(path, name);
    rest.push_back(std::move(path));
  }
  inputs.inputs = std::move(rest);
  return out;
}

}  // namespace m2mlat::analysis
