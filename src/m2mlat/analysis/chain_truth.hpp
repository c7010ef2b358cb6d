// The chains checked against the simulator's truth (sim/full_loop.hpp): each complete chain is matched
// to the manoeuvre whose true LED time is nearest its LED stamp (less the vehicle board's offset), and
// its M2M, G2G and E2E errors (measured - true) and each side's onset error (detected onset less the
// board's offset - true onset) are summarised: median and p5..p95, ns, and the share of the errors
// within the chain's stated U95 (2 u).
//
// The check passes when at least kMinCompletePercent of the manoeuvres give a complete chain, every
// complete chain stands for a distinct manoeuvre (a wrong join would show as a second chain on one),
// and the median E2E error (G2G's on one board, where there is no E2E) is within kMaxMedianErrorNs
// (over kMinChainsForBias chains or more: one slow motion alone may be off by 2 ms, docs/onset.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "m2mlat/analysis/chains.hpp"

namespace m2mlat::analysis {

inline constexpr double kMinCompletePercent = 95;
inline constexpr std::int64_t kMaxMedianErrorNs = 1'000'000;
inline constexpr std::size_t kMinChainsForBias = 10;

struct ErrorStats {
  std::size_t n = 0;
  double median_ns = 0, p5_ns = 0, p95_ns = 0;  // NaN when n = 0
  std::size_t within_u95 = 0;                   // errors within the stated 2 u (of those with a u)
  std::size_t with_u = 0;
};

struct ChainTruthCheck {
  std::size_t manoeuvres = 0;        // true manoeuvres
  std::size_t complete = 0;          // complete chains matched to a manoeuvre
  std::size_t duplicate = 0;         // complete chains on a manoeuvre already taken
  std::array<ErrorStats, 3> errors;  // M2M, G2G, E2E
  ErrorStats station_onset, vehicle_onset;
  double complete_percent() const;
  bool passes() const;
};

ChainTruthCheck check_chains(const ChainResult& result, const sim::FullLoopRun& run);

}  // namespace m2mlat::analysis
