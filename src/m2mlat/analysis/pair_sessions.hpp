// The store session of each pair's cause event, so that a pairs export can name it (with its label) on
// every row. The matcher works on bare timestamp columns with store sequence numbers; the session of
// a sequence number is looked up here, after the analysis, from the store the scenarios came from.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"

namespace m2mlat::analysis {

struct PairSessions {
  // Per result, one entry per match.pairs entry: the cause event's session id (0 = not found).
  // Empty for a result that did not come from the store (ids that are not store seqs).
  std::vector<std::vector<std::int64_t>> sessions;
  std::map<std::int64_t, std::string> labels;  // every session's label, by id
};

// Opens `store_path` read-only (the analysis must have closed it: docs/store.md) and looks up the
// cause events of every result, which must all be scenarios of that store. Memory: 16 bytes a cause
// event of the scenarios while it runs.
PairSessions store_pair_sessions(const std::string& store_path, std::span<const ScenarioResult> results);

}  // namespace m2mlat::analysis
