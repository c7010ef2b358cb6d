// The machine-readable result of `m2mlat stats --json` / `pair --json` / `demo --json`:
// format "m2mlat-stats/1", documented in docs/formats.md. Kept apart from the in-memory types so
// that the wire format is versioned on its own.
#pragma once

#include <nlohmann/json.hpp>
#include <span>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/truth_check.hpp"

namespace m2mlat::report {

inline constexpr const char* kStatsFormat = "m2mlat-stats/1";

nlohmann::json summary_json(const stats::Summary& summary);
nlohmann::json pairing_json(const analysis::ScenarioResult& result);   // counts and unmatched by reason
nlohmann::json scenario_json(const analysis::ScenarioResult& result);  // both of the above + names
// The per-sample uncertainty summary (analysis/uncertainty.hpp); scenario_json adds it as
// "sample_uncertainty" when the scenario's boards had clock samples.
nlohmann::json uncertainty_json(const analysis::UncertaintySummary& summary);
// {"format": "m2mlat-stats/1", "scenarios": [...]}
nlohmann::json stats_document(std::span<const analysis::ScenarioResult> results);
// `pair --json`: the same document with only the scenario's name and its pairing counts.
nlohmann::json pairing_document(std::span<const analysis::ScenarioResult> results);
// `demo --json`: stats_document with each scenario's comparison with the simulator's truth as
// "truth" (checks[k] belongs to results[k]).
nlohmann::json stats_document(std::span<const analysis::ScenarioResult> results,
                              std::span<const analysis::TruthCheck> checks);

}  // namespace m2mlat::report
