// Markers to and from the store's rows (store::MarkerRecord): the store knows nothing of this
// folder's types, so the mapping is here, one function each way.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/markers/marker.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::markers {

// The marker as a row of session `session_id` (the marker's node is the session's).
store::MarkerRecord to_record(const Marker& marker, std::int64_t session_id);
// The row back, with its session's node. Throws core::Error(data) naming the store and row for a
// source name this build does not know.
Marker from_stored(const store::StoredMarker& stored, const std::string& node, const std::string& store_path);

// Every marker of a store (optionally only those of sessions of `scenario`), in time order, each with
// its session's node: what `export --what markers` writes.
std::vector<Marker> store_markers(const store::Store& store, const std::string& scenario = {});

}  // namespace m2mlat::markers
