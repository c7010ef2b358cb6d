// Finding a file's events among those a store holds (rule in already_stored.hpp).
#include "m2mlat/store/already_stored.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <tuple>

namespace m2mlat::store {

std::vector<bool> already_stored(const Store& store, std::span<const core::Event> events) {
  std::vector<bool> out(events.size(), false);
  // The events' time span per node, channel and clock: the store's stamps there are read once per
  // edge as a column (8 bytes a stored event, sorted), and each event looked up in it.
  using Key = std::tuple<std::string, std::string, core::Clock>;
  std::map<Key, std::pair<std::int64_t, std::int64_t>> spans;
  for (const auto& e : events) {
    auto [it, added] = spans.try_emplace(Key{e.node, e.channel, e.time.clock()}, e.time.ns(), e.time.ns());
    it->second = {std::min(it->second.first, e.time.ns()), std::max(it->second.second, e.time.ns())};
  }
  std::map<Key, std::array<std::vector<std::int64_t>, 2>> held;  // by core::Edge
  for (const auto& [key, span] : spans) {
    const auto& [node, channel, clock] = key;
    for (const auto edge : {core::Edge::rising, core::Edge::falling}) {
      EventFilter filter;
      filter.node = node;
      filter.channel = channel;
      filter.edge = edge;
      held[key][static_cast<int>(edge)] =
          store.timestamps(core::TimePoint::from_ns(clock, span.first), core::TimePoint::from_ns(clock, span.second), filter)
              .t_ns;
    }
  }
  for (std::size_t k = 0; k < events.size(); ++k) {
    const auto& e = events[k];
    const auto& stamps = held.at(Key{e.node, e.channel, e.time.clock()})[static_cast<int>(e.edge)];
    out[k] = std::binary_search(stamps.begin(), stamps.end(), e.time.ns());
  }
  return out;
}

}  // namespace m2mlat::store
