#include "m2mlat/markers/stored_markers.hpp"

#include <fmt/format.h>

#include <map>

#include "m2mlat/core/error.hpp"

namespace m2mlat::markers {

store::MarkerRecord to_record(const Marker& m, std::int64_t session_id) {
  store::MarkerRecord r;
  r.session_id = session_id;
  r.name = m.name;
  r.time = m.time;
  r.source = std::string(to_string(m.source));
  if (m.uncertainty) r.uncertainty_ns = m.uncertainty->count();
  r.key = m.key;
  if (m.sender_time) r.sender_ns = m.sender_time->ns();
  r.origin = m.origin;
  return r;
}

Marker from_stored(const store::StoredMarker& stored, const std::string& node, const std::string& store_path) {
  const auto& r = stored.marker;
  const auto source = parse_stamp_source(r.source);
  if (!source)
    core::throw_data_error({store_path, 0},
                           fmt::format("table 'markers' row id {}: field 'source' is '{}', which this m2mlat "
                                       "does not know (written by a newer one?)",
                                       stored.id, r.source));
  Marker m;
  m.node = node;
  m.name = r.name;
  m.time = r.time;
  m.source = *source;
  if (r.uncertainty_ns) m.uncertainty = core::Duration{*r.uncertainty_ns};
  m.key = r.key;
  if (r.sender_ns) m.sender_time = core::TimePoint::from_ns(core::Clock::realtime, *r.sender_ns);
  m.origin = r.origin;
  return m;
}

std::vector<Marker> store_markers(const store::Store& store, const std::string& scenario) {
  std::map<std::int64_t, store::Session> sessions;
  for (auto& s : store.sessions()) sessions.emplace(s.id, std::move(s));
  std::vector<Marker> out;
  for (const auto& stored : store.markers()) {
    const auto it = sessions.find(stored.marker.session_id);
    if (it == sessions.end())
      core::throw_data_error({store.path(), 0}, fmt::format("table 'markers' row id {}: field 'session_id' names "
                                                            "session {}, which does not exist",
                                                            stored.id, stored.marker.session_id));
    if (!scenario.empty() && it->second.scenario != scenario) continue;
    out.push_back(from_stored(stored, it->second.node, store.path()));
  }
  return out;
}

}  // namespace m2mlat::markers
