// Finding a file's events among those a store holds (rule in already_stored.hpp).
#include "m2mlat/store/already_stored.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

namespace m2mlat::store {

std::vector<bool> already_stored(const Store& store, std::span<const core::Event> events) {
  std::vector<bool> out(events.size(), false);
  // One read per node, channel and clock, over the events' time span.
  std::map<std::tuple<std::string, std::string, core::Clock>, std::pair<std::int64_t, std::int64_t>> spans;
  for (const auto& e : events) {
    const auto key = std::tuple{e.node, e.channel, e.time.clock()};
    auto [it, added] = spans.try_emplace(key, e.time.ns(), e.time.ns());
    it->second = {std::min(it->second.first, e.time.ns()), std::max(it->second.second, e.time.ns())};
  }
  std::set<std::tuple<std::string, std::string, core::Clock, core::Edge, std::int64_t>> held;
  for (const auto& [key, span] : spans) {
    const auto& [node, channel, clock] = key;
    EventFilter filter;
    filter.node = node;
    filter.channel = channel;
    for (const auto& s : store.events_in_time(core::TimePoint::from_ns(clock, span.first),
                                              core::TimePoint::from_ns(clock, span.second), filter))
      held.emplace(node, channel, clock, s.event.edge, s.event.time.ns());
  }
  if (held.empty()) return out;
  for (std::size_t k = 0; k < events.size(); ++k) {
    const auto& e = events[k];
    out[k] = held.contains({e.node, e.channel, e.time.clock(), e.edge, e.time.ns()});
  }
  return out;
}

}  // namespace m2mlat::store
