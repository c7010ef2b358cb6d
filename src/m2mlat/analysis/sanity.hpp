// The sanity verdict of an analysed scenario: what makes its figures implausible, each with its
// evidence, so that no implausible result passes as a plain one. One home: every output (stats,
// pair, report, export) shows the warnings of analyse() (text: a "warning:" line; JSON: `warnings`).
//
// Roles that look swapped: the cause's motion comes first, so the true pairing is the one whose
// latency holds steady (network and actuator: tens of ms), while pairing the effect's edges with the
// next cause's edges measures the time to the operator's next move, which varies with the hand
// (seconds). Over the first `kWindow` edges of each side both directions are paired; when the
// reversed one keeps at least 80 % as many pairs with less than half the IQR, or keeps them while the
// effect side's edges come first at the recording's start and end first at its end (each by less
// than the latency window: steering that never rests repeats at a period, and the ends say which
// side moved first), or the typical latency as given is negative, the roles look swapped: the warning
// gives both directions' figures.
#pragma once

#include <string>
#include <vector>

#include "m2mlat/pairing/matcher.hpp"

namespace m2mlat::analysis {

struct ScenarioResult;

struct SanityWarning {
  std::string code;  // "roles_swapped", "no_pairs"; "outside_runs" (pipeline.hpp: a store's events outside any run)
  std::string text;  // one sentence with its evidence
  friend bool operator==(const SanityWarning&, const SanityWarning&) = default;
};

inline constexpr std::size_t kSanityWindow = 4096;  // edges a side paired both ways

// The warnings of one analysed scenario (result.match and result.summary set).
std::vector<SanityWarning> sanity_warnings(const ScenarioResult& result, const pairing::MatchOptions& options);

}  // namespace m2mlat::analysis
