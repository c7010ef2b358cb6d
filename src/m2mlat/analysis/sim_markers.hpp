// The simulator's stage markers (sim/stage_markers.hpp) as markers::Marker values, as a real rig's
// would be read from an m2mlat-markers/1 file: node = the board's name in the run's configuration,
// name = the point, key = the pass's command number, source = host.
#pragma once

#include <vector>

#include "m2mlat/markers/marker.hpp"
#include "m2mlat/sim/stage_markers.hpp"

namespace m2mlat::analysis {

std::vector<markers::Marker> to_markers(const sim::StageMarkers& stages, const sim::RigConfig& config);

}  // namespace m2mlat::analysis
