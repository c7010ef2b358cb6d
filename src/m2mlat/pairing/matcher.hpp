// The cause -> effect matcher: pairs each cause edge with the effect edge it produced.
//
// The problem: a wheel with several magnets fires a burst of edges tens of ms apart on each side,
// while the latency between the sides is ~0.8 s, so many effect edges fall inside every cause's
// latency window. Taking the nearest (or the first) effect after each cause pairs the wrong edges as
// soon as one edge is missed or a spurious one appears. Instead the matcher finds the ONE-TO-ONE,
// ORDER-PRESERVING assignment (if cause a precedes cause b, a's effect precedes b's) that best agrees
// with the locally typical latency, by dynamic programming over the candidate pairs:
//
//  1. a refractory filter removes bounces on each side (refractory.hpp);
//  2. pass 1 aligns against a global reference latency (the mode of all candidate latencies);
//  3. the reference is then made local: a running median (and spread) of the neighbouring pairs;
//  4. pass 2 aligns again against it, the most pairs first (a typical pair, within the local
//     acceptance, counting twice, and once more where it continues its predecessors' sweep at the
//     recording's usual stretch of the spacing), then the best fit; a latency far from the typical one
//     (a stalled link) is still paired where it displaces no typical pair;
//  5. pass 3 repeats pass 2 with the far pairs that an unmatched edge could replace counting nothing.
// Each alignment is exact in integers and deterministic. Its cost is linear in the number of candidate
// pairs (events times the average number of effect edges inside one latency window); its back-tracking
// memory (5 bytes a candidate) is given back block by block once every open chain goes through one pair
// (chain_blocks.hpp). Every event left without a partner is reported with a reason, and every pair the
// data cannot make certain is flagged with the reason (PairFlag). docs/matcher.md has the details.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/pairing/model_match.hpp"
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::pairing {

// Limits that keep the matcher's memory bounded whatever the options say. A latency beyond one day
// is no latency of a teleoperation link; the candidate pairs (5 to 8 bytes each while the chains do
// not meet) bound the memory of the alignment, which follows their number and never the window's width.
inline constexpr core::Duration kMaxLatency{86'400'000'000'000};  // |min_latency|, |max_latency| (ns): 1 day
inline constexpr std::size_t kMaxCandidates = std::size_t{1} << 28;  // candidate pairs (2 GiB of alignment)
// The alignment model keeps every candidate's states and links (about 1 KB a candidate with its
// linked predecessors): 2^22 candidates, a few GiB.
inline constexpr std::size_t kMaxModelCandidates = std::size_t{1} << 22;

struct MatchOptions {
  core::Duration min_latency{0};              // smallest plausible latency (ns); may be negative
  core::Duration max_latency{10'000'000'000};  // largest plausible latency (ns): the window's end
  core::Duration refractory{10'000'000};      // bounce suppression per side (ns); 0 disables
  core::Duration tolerance{0};  // largest |latency - local typical latency| (ns); 0: none, the data decide
  int reference_neighbours = 10;              // running median over this many pairs each side
  core::Duration burst_gap{0};  // edges closer than this (ns) form one burst; 0: burst_gap_for(magnets_deg)
  std::vector<double> magnets_deg;  // the wheels' magnet layout, degrees (empty: one magnet)
  // rules: the passes and flags below; model: the alignment model fitted to the log (model_match.hpp),
  // its pairs below min_probability flagged kPairImprobable.
  enum class Method : std::uint8_t { rules, model };
  Method method = Method::rules;
  double min_probability = 0.99;
};

inline constexpr double kSlowestSteeringDegPerS = 150;
inline constexpr core::Duration kDefaultBurstGap{250'000'000};  // ns

struct MatchResult {
  std::vector<Pair> pairs;           // in cause order (and so in effect order)
  std::vector<Unmatched> unmatched;  // sorted by side, then index
  core::Clock clock = core::Clock::realtime;
  std::int64_t cause_count = 0;  // input sizes, for the reader of a report
  std::int64_t effect_count = 0;
  std::optional<ModelSummary> model;  // with Method::model: the fitted model and its expectation
  std::vector<float> probability;     // with Method::model: each pair's posterior probability (by pair)
  // Cause edges closer than this are one burst (a sweep): burst_gap_of the options. The statistics
  // resample a burst's pairs together (analysis/manoeuvres.hpp).
  core::Duration burst_gap = kDefaultBurstGap;
};

// The burst gap of a magnet layout: the time the slowest steering (kSlowestSteering) takes across the
// widest angle between two neighbouring magnets, at least kDefaultBurstGap (one magnet, or magnets
// close together). A sweep's passes then stay in one burst, so a missed or extra pass flags them.
core::Duration burst_gap_for(std::span<const double> magnets_deg);
// The options' burst_gap, or burst_gap_for their magnets when it is 0.
core::Duration burst_gap_of(const MatchOptions& options);

// Matches two sorted timestamp sequences (ns, same clock). Indices in the result refer to these spans.
// Throws core::Error(usage) on bad options (a window beyond kMaxLatency, or one holding more than
// kMaxCandidates candidate pairs) and core::Error(data) if a sequence is not sorted.
MatchResult match(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                  core::Clock clock, const MatchOptions& options = {});

// The same on two columns the caller lets the matcher rearrange while it runs (two distinct columns):
// each side's edges that are not bounces are moved to the front of its column rather than copied (8
// bytes an edge: 143 MiB at 10^7 edges a side), and both columns are put back as they were, bit for
// bit, before the call returns or throws. The same result as match(). (A name of its own, not an
// overload: a call with a non-const vector would be ambiguous, and the rearranging is then explicit.)
MatchResult match_in_place(std::span<std::int64_t> cause_ns, std::span<std::int64_t> effect_ns,
                           core::Clock clock, const MatchOptions& options = {});

// The same for events (each side's events must share one clock and be in time order).
MatchResult match(std::span<const core::Event> causes, std::span<const core::Event> effects,
                  const MatchOptions& options = {});

}  // namespace m2mlat::pairing
