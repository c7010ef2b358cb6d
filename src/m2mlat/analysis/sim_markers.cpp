#include "m2mlat/analysis/sim_markers.hpp"

#include <string>

namespace m2mlat::analysis {

std::vector<markers::Marker> to_markers(const sim::StageMarkers& stages, const sim::RigConfig& config) {
  std::vector<markers::Marker> out;
  out.reserve(stages.marks.size());
  for (const auto& m : stages.marks) {
    markers::Marker marker;
    marker.node = sim::kStageMarkerBoards[m.point] == core::Role::cause ? config.cause_node : config.effect_node;
    marker.name = std::string(sim::kStageMarkerNames[m.point]);
    marker.time = m.stamp;
    marker.source = markers::StampSource::host;
    marker.key = std::to_string(m.pass);
    marker.origin = "sim";
    out.push_back(std::move(marker));
  }
  return out;
}

}  // namespace m2mlat::analysis
