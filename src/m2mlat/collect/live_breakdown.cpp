#include "m2mlat/collect/live_breakdown.hpp"

#include <algorithm>
#include <climits>
#include <map>

#include "m2mlat/markers/stored_markers.hpp"

namespace m2mlat::collect {

LiveBreakdown::LiveBreakdown(analysis::StageRule rule, core::Duration retry_window)
    : rule_(std::move(rule)), window_(retry_window) {}

std::size_t LiveBreakdown::pull(const store::Store& store) {
  std::size_t n = 0;
  std::map<std::int64_t, std::string> nodes;  // session id -> node, read when a marker needs it
  for (;;) {
    auto rows = store.markers_after(cursor_, 10000);
    if (rows.empty()) break;
    if (nodes.empty())
      for (const auto& s : store.sessions()) nodes.emplace(s.id, s.node);
    std::vector<markers::Marker> more;
    more.reserve(rows.size());
    for (const auto& row : rows) {
      auto it = nodes.find(row.marker.session_id);
      if (it == nodes.end()) {  // a session stored after the map was read
        nodes.clear();
        for (const auto& s : store.sessions()) nodes.emplace(s.id, s.node);
        it = nodes.find(row.marker.session_id);
      }
      // A marker of no session is refused by the store's foreign key; from_stored names it otherwise.
      more.push_back(markers::from_stored(row, it == nodes.end() ? std::string() : it->second, store.path()));
      cursor_ = row.id;
    }
    n += more.size();
    add(std::move(more));
  }
  return n;
}

void LiveBreakdown::add(std::vector<markers::Marker> more) {
  for (auto& m : more) {
    newest_ns_ = std::max(newest_ns_, m.time.ns());
    markers_.push_back(std::move(m));
  }
}

void LiveBreakdown::update(analysis::ScenarioResult& result) {
  if (result.input.scenario != scenario_) {
    frozen_.clear();
    scenario_ = result.input.scenario;
  }
  const auto& pairs = result.match.pairs;
  const auto times = result.times();
  for (const auto& p : pairs) newest_ns_ = std::max(newest_ns_, times.effect(p));
  const auto w = window_.count();
  const auto settled = newest_ns_ == INT64_MIN ? INT64_MIN : newest_ns_ - w;  // effects before it: frozen
  const analysis::MarkerIndex index(markers_);
  std::vector<analysis::EventStages> events;
  std::int64_t oldest_open = settled;  // the earliest cause still joined again
  std::map<std::pair<std::int64_t, std::int64_t>, analysis::EventStages> kept;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!result.in_statistics(i)) continue;
    const auto& p = pairs[i];
    const std::pair key{times.cause(p), times.effect(p)};
    analysis::EventStages e;
    if (const auto it = frozen_.find(key); it != frozen_.end()) {
      e = it->second;
    } else {
      e = analysis::event_stages(key.first, key.second, result.match.clock, rule_, index);
    }
    e.pair = i;
    e.cause_id = result.cause_seq(p);
    if (key.second < settled)
      kept.emplace(key, e);
    else
      oldest_open = std::min(oldest_open, key.first);
    events.push_back(std::move(e));
  }
  frozen_ = std::move(kept);  // pairs no longer found (re-paired otherwise) are forgotten
  result.breakdown = analysis::summarize_stages(std::move(events), rule_);
  // Markers before every open pair's cause, less a window (a selector may find one shortly before a
  // cause, to report it out of order), are no longer looked at.
  if (oldest_open != INT64_MIN) {
    const auto drop_before = oldest_open - w;
    std::erase_if(markers_, [drop_before](const markers::Marker& m) { return m.time.ns() < drop_before; });
  }
}

}  // namespace m2mlat::collect
