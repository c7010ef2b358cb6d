// A scenario's breakdown into stages (breakdown.hpp) over the pairs its statistics are over, kept
// in the ScenarioResult for every output. `stats`, `report` and the live view call it after the
// pipeline with the markers they have.
#pragma once

#include "m2mlat/analysis/breakdown.hpp"
#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::analysis {

// Sets result.breakdown over the pairs in_statistics (in pair order). Throws core::Error(data)
// naming the scenario when its events are not on CLOCK_REALTIME.
void attach_breakdown(ScenarioResult& result, const StageRule& rule, const MarkerIndex& index);

}  // namespace m2mlat::analysis
