// A matched cause -> effect pair and the reasons an event can stay unmatched.
#pragma once

#include <cstdint>
#include <string_view>

#include "m2mlat/core/time.hpp"

namespace m2mlat::pairing {

// Bits of Pair::flags. Exported: never renumber.
enum PairFlag : std::uint32_t {
  // The pair's burst of edges (on either side) has an edge without partner: a magnet pass was missed
  // on one side or an extra edge appeared, so which edge belongs to which may be ambiguous. Such
  // pairs are reported but left out of the statistics unless asked for (docs/matcher.md).
  kPairAmbiguous = 1u << 0,
  // An unmatched edge could take the pair's place (alone, or by shifting neighbouring pairs by one)
  // and the pairing so changed fits nearly as well: a lost edge next to a spurious one, or a real
  // outlier next to an edge that fits better.
  kPairCompeting = 1u << 1,
  // The latency lies far from its neighbours' (beyond the local acceptance) and is not confirmed as a
  // jump of the link's latency by its neighbours (docs/matcher.md).
  kPairJump = 1u << 2,
  // The cause or effect edge was followed, within the refractory period, by edges dropped as bounces
  // for longer than kBounceSpanLimit: the pass's edge may be one of the later ones, so the latency may
  // be off by up to that span (a spurious edge just before the true one looks like this).
  kPairBounced = 1u << 3,
  // Set by the analysis from the boards' clock records (analysis/clock_steps), not by the matcher:
  // an edge of the pair was corrected by a clock step of known size (its uncertainty includes the
  // step's), ...
  kPairStepCorrected = 1u << 8,
  // ... or came after a step of unknown size: the pair is left out of the statistics.
  kPairAfterClockStep = 1u << 9,
};
inline constexpr std::uint32_t kPairUncertain = kPairAmbiguous | kPairCompeting | kPairJump | kPairBounced;
// A cluster of edges no longer than this is one pass and its contact bounce: its first edge is taken,
// and the latency is right to within this (less than the clock terms of docs/precision.md).
inline constexpr core::Duration kBounceSpanLimit{3'000'000};  // ns

// One latency sample: the cause edge and the effect edge it produced. Both timestamps are on the
// match's clock (CLOCK_REALTIME of two synchronised boards in the field); latency = effect - cause.
struct Pair {
  // The two events' indices in the input that was paired: 4 bytes each (the matcher takes fewer than
  // 2^31 events a side; pulse pairing and a pairs file's rows check theirs), so that a pair is 32
  // bytes (298 MB at 9.3 million pairs, not 372).
  std::uint32_t cause_index = 0;
  std::uint32_t effect_index = 0;
  // The two edges' times, ns on the clock of the pairs' MatchResult (one clock for all the pairs of a
  // match, so it is not repeated in each).
  std::int64_t cause_ns = 0;
  std::int64_t effect_ns = 0;
  std::uint32_t flags = 0;  // PairFlag bits
  // How long the edges dropped as bounces went on after the cause edge, plus after the effect edge, ns
  // (0 without bounces; saturated at 2^31 - 1). The matcher takes each cluster's first edge; if that
  // was a spurious edge just before the true one, the latency is off by up to this: the worst-case
  // bound of the pair (analysis/uncertainty.hpp) includes it. (Beside the flags: no padding.)
  std::int32_t bounce_span_ns = 0;

  core::Duration latency() const { return core::Duration{effect_ns - cause_ns}; }
  // Any reason to doubt the pair: such pairs stay out of the statistics unless asked for.
  bool ambiguous() const { return (flags & kPairUncertain) != 0; }
  friend bool operator==(const Pair&, const Pair&) = default;
};
static_assert(sizeof(Pair) == 32, "a pair is four words: 10^7 of them are 320 MB");

enum class Side : std::uint8_t { cause = 0, effect = 1 };
std::string_view to_string(Side side);

// Why an event has no partner. Stored and exported by name: keep the names stable.
enum class UnmatchedReason : std::uint8_t {
  bounce = 0,        // within the refractory period after a kept edge on the same side
  no_candidate = 1,  // no event on the other side within the latency window
  outmatched = 2,    // candidates existed, but a consistent one-to-one ordering used them elsewhere
};
std::string_view to_string(UnmatchedReason reason);

struct Unmatched {
  std::int64_t index = 0;  // index in the matcher's input on that side
  core::TimePoint time;
  // The two one-byte fields last, side by side: 32 bytes rather than 40 (an unmatched event is a few
  // per cent of the events, and the list is held beside the pairs).
  Side side = Side::cause;
  UnmatchedReason reason = UnmatchedReason::no_candidate;
  friend bool operator==(const Unmatched&, const Unmatched&) = default;
};
static_assert(sizeof(Unmatched) == 32, "index, time, and the two one-byte fields together");

}  // namespace m2mlat::pairing
