// The packet markers and one-way times as files and documents: `m2mlat-markers/1` (one line per
// marker) and `m2mlat-oneway/1` (one line per command matched across two captures), each as CSV
// and as JSON (docs/formats.md). Written here only; the in-memory types are marker.hpp and
// one_way.hpp.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>

#include "m2mlat/markers/marker.hpp"
#include "m2mlat/markers/one_way.hpp"
#include "m2mlat/markers/packet_markers.hpp"

namespace m2mlat::markers {

inline constexpr std::string_view kMarkersFormat = "m2mlat-markers/1";
inline constexpr std::string_view kOneWayFormat = "m2mlat-oneway/1";

std::string markers_csv(std::span<const Marker> markers);
nlohmann::json markers_json(std::span<const Marker> markers, const CaptureCounts& counts);
nlohmann::json counts_json(const CaptureCounts& counts);

std::string one_way_csv(const OneWayMatch& match);
// The commands, their summary and the unmatched counts of both captures.
nlohmann::json one_way_json(const OneWayMatch& match, const CaptureCounts& sender, const CaptureCounts& receiver);

}  // namespace m2mlat::markers
