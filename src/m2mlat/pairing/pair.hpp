// A matched cause -> effect pair and the reasons an event can stay unmatched.
#pragma once

#include <cstdint>
#include <span>
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
  // outlier next to an edge that fits better. Also a pair next to a kPairJump pair whose edge it would
  // fit nearly as well: it may have given its true partner to the jump.
  kPairCompeting = 1u << 1,
  // The latency lies far from its neighbours' (beyond the local acceptance) and is not confirmed as a
  // jump of the link's latency by its neighbours (docs/matcher.md).
  kPairJump = 1u << 2,
  // The cause or effect edge was followed, within the refractory period, by edges dropped as bounces
  // for longer than kBounceSpanLimit: the pass's edge may be one of the later ones, so the latency may
  // be off by up to that span (a spurious edge just before the true one looks like this).
  kPairBounced = 1u << 3,
  // The alignment model (`--matcher model`, model_match.hpp) gives the pair a posterior probability
  // below the level asked for (`--min-probability`, 0.99): left out of the statistics like the others.
  kPairImprobable = 1u << 4,
  // Set by the analysis from the boards' clock records (analysis/clock_steps), not by the matcher:
  // an edge of the pair was corrected by a clock step of known size (its uncertainty includes the
  // step's), ...
  kPairStepCorrected = 1u << 8,
  // ... or came after a step of unknown size: the pair is left out of the statistics.
  kPairAfterClockStep = 1u << 9,
};
inline constexpr std::uint32_t kPairUncertain = kPairAmbiguous | kPairCompeting | kPairJump | kPairBounced | kPairImprobable;
// A cluster of edges no longer than this is one pass and its contact bounce: its first edge is taken,
// and the latency is right to within this (less than the clock terms of docs/precision.md).
inline constexpr core::Duration kBounceSpanLimit{3'000'000};  // ns

// One latency sample: the cause edge and the effect edge it produced, by their indices in the two
// columns that were paired. The times are not repeated here: they are the columns' (PairTimes), so
// that a pair is 16 bytes (149 MB at 9.3 million pairs, not 298, beside the columns that hold them
// anyway).
struct Pair {
  // The two events' indices in the input that was paired: 4 bytes each (the matcher takes fewer than
  // 2^31 events a side; a pairs file's rows are checked, analysis/pairs_file.hpp).
  std::uint32_t cause_index = 0;
  std::uint32_t effect_index = 0;
  std::uint32_t flags = 0;  // PairFlag bits
  // How long the edges dropped as bounces went on after the cause edge, plus after the effect edge, ns
  // (0 without bounces; saturated at 2^31 - 1). The matcher takes each cluster's first edge; if that
  // was a spurious edge just before the true one, the latency is off by up to this: the worst-case
  // bound of the pair (analysis/uncertainty.hpp) includes it.
  std::int32_t bounce_span_ns = 0;

  // Any reason to doubt the pair: such pairs stay out of the statistics unless asked for.
  bool ambiguous() const { return (flags & kPairUncertain) != 0; }
  friend bool operator==(const Pair&, const Pair&) = default;
};
static_assert(sizeof(Pair) == 16, "a pair is two indices, its flags and its bounce span");

// The times of a match's pairs: the two columns that were paired, ns on the clock of the pairs'
// MatchResult (CLOCK_REALTIME of two synchronised boards in the field); latency = effect - cause.
// It borrows the columns: keep them alive and unchanged while it is used.
struct PairTimes {
  std::span<const std::int64_t> cause_ns, effect_ns;

  std::int64_t cause(const Pair& p) const { return cause_ns[p.cause_index]; }
  std::int64_t effect(const Pair& p) const { return effect_ns[p.effect_index]; }
  core::Duration latency(const Pair& p) const { return core::Duration{effect(p) - cause(p)}; }
};

enum class Side : std::uint8_t { cause = 0, effect = 1 };
std::string_view to_string(Side side);

// Why an event has no partner. Stored and exported by name: keep the names stable.
enum class UnmatchedReason : std::uint8_t {
  bounce = 0,        // within the refractory period after a kept edge on the same side
  no_candidate = 1,  // no event on the other side within the latency window
  outmatched = 2,    // candidates existed, but a consistent one-to-one ordering used them elsewhere
};
std::string_view to_string(UnmatchedReason reason);

// An event without partner, by its index in the matcher's input on its side (fewer than 2^31 a side):
// its time is that column's, as a pair's are (PairTimes). 8 bytes: the list is held beside the pairs.
struct Unmatched {
  std::uint32_t index = 0;
  Side side = Side::cause;
  UnmatchedReason reason = UnmatchedReason::no_candidate;
  friend bool operator==(const Unmatched&, const Unmatched&) = default;
};
static_assert(sizeof(Unmatched) == 8, "an index and the two one-byte fields");

}  // namespace m2mlat::pairing
