// Order-preserving one-to-one alignment of cause and effect edges (see matcher.hpp for the method).
#include "m2mlat/pairing/matcher.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/pairing/chain_blocks.hpp"
#include "m2mlat/pairing/refractory.hpp"

namespace m2mlat::pairing {

namespace {

constexpr std::uint32_t kNone = kNoCandidate;
constexpr std::size_t kMaxEvents = std::size_t{1} << 31;  // per side: a chain's count (2 a pair) fits 32 bits
static_assert(kMaxCandidates < kNone, "candidate ids are 32 bits, kNone excluded");
static_assert(3 * kMaxCandidates < kNone, "a chain's count (3 a pair at most) fits 32 bits");
constexpr std::int64_t kAllBounces = std::numeric_limits<std::int64_t>::max();  // see match()

// Gives a vector's memory back now. (`v = {}` would not: it picks the initializer_list assignment,
// which clears the vector but keeps its capacity.)
template <typename Vector>
void free_now(Vector& v) {
  Vector().swap(v);
}

// The kept (non-bounce) edges of one side, moved to the front of the caller's column in place: no
// copy of them (8 bytes an edge), only the bounces' times kept beside their indices (16 bytes a
// bounce: a few per cent of the edges). `bounces` maps kept positions back to input indices
// (KeptIndex), so that no table of input indices is kept. restore() puts the column back as it was;
// the destructor does it if match_in_place() leaves by an exception.
struct Kept {
  std::vector<std::int64_t> bounces;    // ascending input indices
  std::vector<std::int64_t> bounce_ns;  // their timestamps (ns), saved before the kept edges move over them
  std::span<const std::int64_t> ns;     // the kept timestamps (ns): the front of the column until restore()

  Kept(std::span<std::int64_t> column, core::Duration refractory)
      : bounces(refractory_bounces(column, refractory)), column_(column) {
    bounce_ns.reserve(bounces.size());  // before anything moves: a bad_alloc leaves the column as it was
    // Edges before the first bounce stay where they are; each later kept edge moves forward by the
    // number of bounces before it.
    std::size_t k = bounces.empty() ? column.size() : static_cast<std::size_t>(bounces.front());
    for (std::size_t i = k, b = 0; i < column.size(); ++i) {
      if (b < bounces.size() && bounces[b] == static_cast<std::int64_t>(i))
        bounce_ns.push_back(column[i]), ++b;
      else
        column[k++] = column[i];
    }
    ns = column.first(k);
  }
  Kept(const Kept&) = delete;  // restores the column once
  Kept& operator=(const Kept&) = delete;
  ~Kept() { restore(); }

  // Moves the kept edges back to their input indices and the bounces' times into the gaps, from the
  // column's end (an edge only moves back, onto a slot already read), and stops at the first bounce:
  // the edges before it never moved. `ns` is no longer valid afterwards.
  void restore() noexcept {
    if (restored_) return;
    restored_ = true;
    std::size_t k = ns.size();
    for (std::size_t i = column_.size(), b = bounces.size(); b > 0;) {
      --i;
      if (bounces[b - 1] == static_cast<std::int64_t>(i))
        column_[i] = bounce_ns[--b];
      else
        column_[i] = column_[--k];
    }
    ns = {};
    free_now(bounce_ns);  // held beside the pairs otherwise
  }

 private:
  std::span<std::int64_t> column_;
  bool restored_ = false;
};

// For cause i, its candidate effects are [lo, hi): those with latency in [min, max]. Both ends only
// move forward as i grows, so each pass walks them along instead of storing them (8 bytes a cause).
class Window {
 public:
  Window(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects, std::int64_t min_ns,
         std::int64_t max_ns)
      : causes_(causes), effects_(effects), min_ns_(min_ns), max_ns_(max_ns) {}
  // Moves to cause i; i must not decrease from one call to the next.
  void at(std::size_t i) {
    while (lo < effects_.size() && effects_[lo] - causes_[i] < min_ns_) ++lo;
    if (hi < lo) hi = lo;
    while (hi < effects_.size() && effects_[hi] - causes_[i] <= max_ns_) ++hi;
  }
  std::uint32_t lo = 0, hi = 0;

 private:
  std::span<const std::int64_t> causes_, effects_;
  std::int64_t min_ns_, max_ns_;
};

// What every pass needs: the two sides' kept timestamps and the latency window.
struct Sides {
  std::span<const std::int64_t> causes, effects;
  std::int64_t min_ns, max_ns;
  Window window() const { return Window(causes, effects, min_ns, max_ns); }
};

// The number of candidate pairs (the sum over causes of the number of effects in their window), the
// same per block of causes (ChainBlocks::kBlockCauses) and the widest window, counted by walking the
// windows. Every pass takes them from here.
struct CandidateCount {
  std::size_t total = 0, widest = 1;
  std::vector<std::size_t> per_block;
};
CandidateCount candidate_count(const Sides& sides) {
  CandidateCount count;
  count.per_block.assign(sides.causes.size() / ChainBlocks::kBlockCauses + 1, 0);
  Window w = sides.window();
  for (std::size_t i = 0; i < sides.causes.size(); ++i) {
    w.at(i);
    count.total += w.hi - w.lo;
    count.per_block[i / ChainBlocks::kBlockCauses] += w.hi - w.lo;
    count.widest = std::max<std::size_t>(count.widest, w.hi - w.lo);
  }
  return count;
}

// Global reference latency: the centre of the densest 100 ms-wide bin of all candidate latencies.
// True pairs pile up around the typical latency; wrong candidates spread over the whole window.
// The counts are kept for the occupied bins only, so that memory follows the number of candidates
// and never the window's width: a table of every bin while there are fewer bins than candidates,
// else each candidate's bin, sorted.
std::int64_t global_reference(const Sides& sides, std::size_t candidates) {
  constexpr std::int64_t kBin = 100'000'000;  // ns
  const auto bin_count = static_cast<std::size_t>((sides.max_ns - sides.min_ns) / kBin + 1);
  // Calls use(bin) for every candidate. (The names are bound inside: C++20 lets clang capture no
  // structured binding.)
  const auto for_each_bin = [&sides](auto&& use) {
    const auto& [causes, effects, min_ns, max_ns] = sides;
    Window w = sides.window();
    for (std::size_t i = 0; i < causes.size(); ++i) {
      w.at(i);
      for (auto j = w.lo; j < w.hi; ++j)
        use(static_cast<std::size_t>((effects[j] - causes[i] - min_ns) / kBin));
    }
  };
  std::vector<std::pair<std::size_t, std::int64_t>> occupied;  // (bin, count), ascending bins
  if (bin_count <= candidates) {
    std::vector<std::int64_t> counts(bin_count, 0);
    for_each_bin([&](std::size_t bin) { ++counts[bin]; });
    for (std::size_t b = 0; b < bin_count; ++b)
      if (counts[b] > 0) occupied.emplace_back(b, counts[b]);
  } else {
    std::vector<std::size_t> bins;
    bins.reserve(candidates);
    for_each_bin([&](std::size_t bin) { bins.push_back(bin); });
    std::sort(bins.begin(), bins.end());
    for (std::size_t k = 0; k < bins.size(); ++k) {
      if (occupied.empty() || occupied.back().first != bins[k]) occupied.emplace_back(bins[k], 0);
      ++occupied.back().second;
    }
  }
  // The fullest bin; of equal ones the first (the shorter latency: a chain shifted by one edge makes
  // a peak one edge interval later, with one pair fewer). Bins of 100 ms hold the bulk of a typical
  // latency's spread (tens of ms); no smoothing over neighbours, which would let a periodic signal's
  // shifted peak, one period later, win by its own neighbours.
  std::size_t best_bin = 0;
  std::int64_t best_count = -1;
  for (const auto& [bin, count] : occupied)
    if (count > best_count) best_count = count, best_bin = bin;
  return sides.min_ns + static_cast<std::int64_t>(best_bin) * kBin + kBin / 2;
}

// One alignment pass: the order-preserving one-to-one set of candidate pairs with the largest count
// (count per pair), then the largest total value. `row_of(i)` gives cause i's rule (PassRow): its
// value(latency), the worth of pairing cause i at that latency (ns of the window), > 0 to be allowed,
// kDisallowed to forbid; count(value); and follows(j), the extra count of the pair (i, j) continuing
// its predecessors' sweep. Taking the rule once per cause keeps what is the same for the whole row
// (the reference, the acceptance, the cause's interval) out of the loop over its candidates. Returns
// for each cause the matched effect or kNone.
//
// G(i, j) = (count, value)(i, j) + max(0, max{ G(i', j') : i' < i, j' < j },
// G(i - 1, j - 1) + (follows(i, j), 0), G(i - 1, j - 2) + (skip(i, j), 0)) is the best (count, then
// value) of an ordered chain of pairs ending in (i, j); follows(i, j) is the extra count of a pair that
// continues its predecessors' sweep, skip(i, j) the same over an effect whose cause was lost
// (SweepStretch::Link), both found in the previous cause's row, which is kept. Causes are processed in
// order; for effects we keep best[j] = max over the causes so far of G(., j). Because candidate windows
// only move forward, effects left behind by the window are folded into one `frozen` maximum, so each
// cause costs O(its window), and best[] only needs the effects inside the current window: it is a ring
// of the widest window's size (a power of two), not one entry per effect. Each candidate's predecessor
// goes to `chains` (ChainBlocks), handed the ends of the open chains after every block: it writes out
// the chains as they meet and gives their memory back.
//
// A chain's (count, value) is one unsigned key, count << shift | value, compared and added as one
// number, so that every maximum is a conditional move rather than a branch the data mispredict. The
// key is 64 bits when the largest count and total value of any chain fit (AlignKey), else 128.
constexpr std::int64_t kDisallowed = -1;

__extension__ typedef unsigned __int128 WideKey;  // GCC and Clang, on every 64-bit target

template <typename Key, typename RowOf>
std::vector<std::uint32_t> align(const Sides& sides, const CandidateCount& count, ChainBlocks& chains,
                                 unsigned shift, RowOf row_of) {
  const auto& [causes, effects, min_ns, max_ns] = sides;
  const std::size_t widest = count.widest;
  const bool narrow = widest <= 256;  // every offset in a window fits a byte
  chains.start(causes.size(), narrow);
  ChainBlocks::Rows rows{};    // the open block's arrays, indexed from its first candidate and cause
  std::uint32_t first_id = 0;  // the open block's first candidate
  std::size_t first_cause = 0;
  std::uint32_t next_id = 0;  // candidates written so far (at most count.total)
  std::size_t ring_size = 1;
  while (ring_size < widest) ring_size *= 2;
  const std::size_t mask = ring_size - 1;
  // A chain is its key ((count << shift) + its total value) and its last candidate (kNone: the empty
  // chain), kept in separate arrays and scalars: a maximum is then two conditional moves.
  // best[j & mask] for the effects j in [folded, window end); frozen: the best over effects [0, folded).
  std::vector<Key> best_key_store(ring_size, 0);
  std::vector<std::uint32_t> best_candidate_store(ring_size, kNone);
  Key* const best_key = best_key_store.data();
  std::uint32_t* const best_candidate = best_candidate_store.data();
  Key frozen_key = 0;
  std::uint32_t frozen_candidate = kNone;
  std::size_t folded = 0;
  // This cause's chain ends, applied after the row, and the previous cause's: effect, key (the chain's
  // last candidate is the row's own), at most the widest window's each.
  std::vector<std::uint32_t> row_effect_store(widest), previous_effect_store(widest);
  std::vector<std::uint32_t> row_id_store(widest), previous_id_store(widest);
  std::vector<Key> row_key_store(widest), previous_key_store(widest);
  std::uint32_t *row_effect = row_effect_store.data(), *previous_effect = previous_effect_store.data();
  std::uint32_t *row_id = row_id_store.data(), *previous_id = previous_id_store.data();
  Key *row_key = row_key_store.data(), *previous_key = previous_key_store.data();
  std::size_t row_size = 0, previous_size = 0;
  // The ends of every chain a later cause can extend: the frozen one, each effect's best, the last row's.
  std::vector<std::uint32_t> ends;
  ends.reserve(1 + ring_size + widest);
  const auto live_ends = [&]() -> std::span<const std::uint32_t> {
    ends.clear();
    if (frozen_candidate == kNone) return {};  // a chain may still start anywhere: nothing is settled
    ends.push_back(frozen_candidate);
    for (std::size_t s = 0; s < ring_size; ++s)
      if (best_candidate[s] != kNone) ends.push_back(best_candidate[s]);
    ends.insert(ends.end(), row_id, row_id + row_size);
    return ends;
  };

  Window w = sides.window();
  for (std::size_t i = 0; i < causes.size(); ++i) {
    w.at(i);
    if (i % ChainBlocks::kBlockCauses == 0) {
      if (i > 0) {
        chains.close(next_id);
        chains.settle(live_ends());
      }
      rows = chains.open(i, next_id, count.per_block[i / ChainBlocks::kBlockCauses]);
      first_id = next_id, first_cause = i;
    }
    rows.row_start[i - first_cause] = next_id;
    rows.row_lo[i - first_cause] = w.lo;
    for (; folded < w.lo; ++folded) {
      const std::size_t slot = folded & mask;
      const bool up = best_key[slot] > frozen_key;
      frozen_key = up ? best_key[slot] : frozen_key;
      frozen_candidate = up ? best_candidate[slot] : frozen_candidate;
      best_key[slot] = 0, best_candidate[slot] = kNone;  // the slot now serves effect folded + ring_size
    }
    const auto rule = row_of(i);
    const std::int64_t cause = causes[i];
    Key running_key = frozen_key;  // max over effects < j, from causes < i
    std::uint32_t running_candidate = frozen_candidate;
    std::swap(row_effect, previous_effect);
    std::swap(row_id, previous_id);
    std::swap(row_key, previous_key);
    previous_size = row_size;
    row_size = 0;
    std::size_t skipping = 0;  // previous[skipping]: the previous cause's chain end at effect j - 2, if any
    std::size_t adjacent = 0;  // previous[adjacent]: the previous cause's chain end at effect j - 1, if any
    for (auto j = w.lo; j < w.hi; ++j) {
      const std::int64_t v = rule.value(effects[j] - cause);
      if (v > 0) {
        const std::uint32_t id = next_id++;
        const Key gain = (Key{rule.count(v)} << shift) + static_cast<Key>(v);
        Key chain = running_key + gain;
        std::uint32_t pred = running_candidate;
        if (rule.follows.skips && j > 1) {  // over an effect left unpaired (its cause lost): SweepStretch
          while (skipping < previous_size && previous_effect[skipping] + 2 < j) ++skipping;
          if (skipping < previous_size && previous_effect[skipping] + 2 == j) {
            const Key linked = previous_key[skipping] + gain + (Key{rule.follows.skip(j)} << shift);
            const bool link = linked > chain;
            chain = link ? linked : chain;
            pred = link ? previous_id[skipping] : pred;
          }
        }
        while (adjacent < previous_size && previous_effect[adjacent] + 1 < j) ++adjacent;
        if (i > 0 && j > 0 && adjacent < previous_size && previous_effect[adjacent] + 1 == j) {
          const Key linked = previous_key[adjacent] + gain + (Key{rule.follows(j)} << shift);
          const bool link = linked > chain;
          chain = link ? linked : chain;
          pred = link ? previous_id[adjacent] : pred;
        }
        if (narrow)
          rows.offset[id - first_id] = static_cast<std::uint8_t>(j - w.lo);
        else
          rows.effect[id - first_id] = j;
        rows.pred[id - first_id] = pred;
        row_effect[row_size] = j, row_key[row_size] = chain, row_id[row_size] = id;
        ++row_size;
      }
      const std::size_t slot = j & mask;
      const bool up = best_key[slot] > running_key;
      running_key = up ? best_key[slot] : running_key;
      running_candidate = up ? best_candidate[slot] : running_candidate;
    }
    for (std::size_t r = 0; r < row_size; ++r) {
      const std::size_t slot = row_effect[r] & mask;
      const bool up = row_key[r] > best_key[slot];
      best_key[slot] = up ? row_key[r] : best_key[slot];
      best_candidate[slot] = up ? row_id[r] : best_candidate[slot];
    }
  }
  if (!causes.empty()) chains.close(next_id);

  // Effects past the last window were never written: their slots hold the empty chain.
  Key overall_key = frozen_key;
  std::uint32_t overall = frozen_candidate;
  for (std::size_t j = folded; j < std::min<std::size_t>(effects.size(), folded + ring_size); ++j) {
    const bool up = best_key[j & mask] > overall_key;
    overall_key = up ? best_key[j & mask] : overall_key;
    overall = up ? best_candidate[j & mask] : overall;
  }
  return chains.finish(overall);
}

// The vehicle's wheel may turn at half the operator's speed: its bursts take a gap this many times wider.
constexpr std::int64_t kVehicleGapFactor = 2;
// How far the stretch of a sweep's spacing (effect interval / cause interval) may stray from its median
// over the recording, either way, for true consecutive pairs: the vehicle's wheel turns at 0.6-0.95 of
// the operator's speed, and its lag differs from pass to pass by tens of ms. (3/2, as a fraction, so
// that the alignment stays in integers.)
constexpr double kPatternFactor = 1.5;
constexpr std::int64_t kPatternNumerator = 3, kPatternDenominator = 2;
// Stretches below this (millionths: effects ten times closer than their causes) are left out of the
// band's median: that is a stalled link's queue draining (its commands released together, the effects
// tens of ms apart for causes hundreds apart), not a wheel replaying a sweep. Counted in, they pulled
// the median of four-magnet logs with stalls from about 1.3 to 0.9 and centred the band on noise.
constexpr std::int64_t kQueueDrainStretch = 100'000;

// The stretch of the effect side's spacing against the cause side's, in millionths: for two
// consecutive pairs (i - 1, j - 1) and (i, j), 10^6 x effect interval / cause interval. The vehicle's
// wheel replays the operator's sweep at a similar speed, so the true pairs of a sweep keep near one
// stretch, while a chain shifted by one pass compares the intervals of different passes and breaks it
// wherever the spacing changes (at each end of a sweep, and at every lost or extra pass). Only passes
// of one sweep on both sides (closer than the burst gap) are compared: between manoeuvres the spacing
// follows the operator, not the wheel. The band is kPatternFactor either side of the median stretch of
// the previous pass's consecutive pairs; an alignment pass counts a pair that follows its cause's and
// its effect's predecessors within the band once more (SweepStretch::follows).
class SweepStretch {
 public:
  SweepStretch(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
               std::int64_t gap_ns, std::size_t magnets)
      : causes_(causes), effects_(effects), gap_ns_(gap_ns), pass_short_(causes.size(), false) {
    // A burst one pass short of a multiple of the magnets (a sweep with a lost pass): its causes may
    // link over the effect of the lost pass (Link::skip). Only there: elsewhere a link over an effect
    // is a chain that leaves a true effect out (a stall's queued effects lie a few ms apart, and twice
    // a slow sweep's interval may lie in the band).
    if (magnets < 2) return;
    for (std::size_t k = 0, first = 0; k <= causes.size(); ++k)
      if (k == causes.size() || (k > first && causes[k] - causes[k - 1] >= gap_ns)) {
        if ((k - first) % magnets == magnets - 1)
          for (std::size_t q = first; q < k; ++q) pass_short_[q] = true;
        first = k;
      }
  }

  // The band from the consecutive pairs of an alignment (matched effect per cause, or kNone).
  void fit(const std::vector<std::uint32_t>& matched) {
    // Walked twice, to count and to collect: grown by doubling, the list was up to 16 bytes a pair at
    // a peak of `m2mlat stats`.
    const auto for_each_stretch = [&](auto&& take) {
      for (std::size_t i = 1; i < matched.size(); ++i)
        if (matched[i] != kNone && matched[i - 1] != kNone && matched[i - 1] + 1 == matched[i]) {
          const std::int64_t s = stretch(i, matched[i]);
          if (s >= kQueueDrainStretch) take(s);
        }
    };
    std::size_t count = 0;
    for_each_stretch([&](std::int64_t) { ++count; });
    std::vector<std::int64_t> stretches;
    stretches.reserve(count);
    for_each_stretch([&](std::int64_t s) { stretches.push_back(s); });
    low_ = 1, high_ = 0;  // no band
    low_reach_ = reach(low_), high_reach_ = reach(high_ + 1);
    if (stretches.size() < 2) return;
    const auto mid = stretches.begin() + static_cast<std::ptrdiff_t>(stretches.size() / 2);
    std::nth_element(stretches.begin(), mid, stretches.end());
    low_ = *mid * kPatternDenominator / kPatternNumerator;
    high_ = *mid * kPatternNumerator / kPatternDenominator;
    low_reach_ = reach(low_), high_reach_ = reach(high_ + 1);
  }

  // Whether the pairs (i - 1, j - 1) -> (i, j) follow each other within one sweep and within the band,
  // for one cause i > 0 and any effect j > 0: Link(j) is 1 then, else 0. The same test as
  // low_ <= stretch(i, j) <= high_, without a division per candidate: for x = 10^6 x the effect
  // interval (< 10^18) and the cause interval c > 0, floor(x / c) >= low exactly when x >= low x c,
  // and <= high exactly when x < (high + 1) x c; the two products are taken once per cause (a product
  // beyond 64 bits is beyond every x: no pair reaches the band's low end, every pair is below its
  // high end).
  struct Link {
    const std::int64_t* effects = nullptr;  // null: cause i starts no link (first cause, or a gap before it)
    std::int64_t effect_limit = 0, low_x = 0, high_x = 0;
    bool skips = false;  // the cause's burst is a pass short: skip() may link
    std::uint32_t operator()(std::uint32_t j) const { return within(j, 1); }
    // The same for (i - 1, j - 2) -> (i, j), effect j - 1 left unpaired (j > 1): a pass lost on the
    // cause side inside a sweep leaves two consecutive causes two passes apart, whose effects are then
    // two apart. Without it, a chain shifted by one pass (cause i with effect j - 1) lies as close to
    // the typical latency and breaks no link either, and the lost pass's effect pulls the rest of the
    // sweep off by one.
    std::uint32_t skip(std::uint32_t j) const { return skips ? within(j, 2) : 0u; }
    std::uint32_t within(std::uint32_t j, std::uint32_t back) const {
      if (effects == nullptr) return 0;
      const std::int64_t effect_interval = effects[j] - effects[j - back];
      if (effect_interval >= effect_limit) return 0;
      const std::int64_t x = effect_interval * 1'000'000;
      return x >= low_x && x < high_x ? 1u : 0u;
    }
  };
  Link link(std::size_t i) const {
    if (i == 0) return {};
    const std::int64_t cause_interval = causes_[i] - causes_[i - 1];
    if (cause_interval <= 0 || cause_interval >= gap_ns_) return {};
    // band x cause_interval, or kLargest beyond 64 bits (the division that tells is taken once a fit)
    const auto times = [&](std::int64_t band, std::int64_t band_reach) {
      return cause_interval > band_reach ? kLargest : band * cause_interval;
    };
    return {effects_.data(), std::min(kVehicleGapFactor * gap_ns_, kMaxInterval), times(low_, low_reach_),
            times(high_ + 1, high_reach_), pass_short_[i]};
  }

 private:
  // The stretch of (i - 1, j - 1) -> (i, j) in millionths, or -1 when either interval spans a burst gap
  // (the vehicle's side: kVehicleGapFactor of it) or kMaxInterval, so that 10^6 times it fits 64 bits
  // whatever burst gap was given.
  static constexpr std::int64_t kMaxInterval = 1'000'000'000'000;  // ns: 1000 s
  std::int64_t stretch(std::size_t i, std::uint32_t j) const {
    const std::int64_t cause_interval = causes_[i] - causes_[i - 1], effect_interval = effects_[j] - effects_[j - 1];
    if (cause_interval <= 0 || cause_interval >= gap_ns_ || effect_interval >= kVehicleGapFactor * gap_ns_ ||
        effect_interval >= kMaxInterval)
      return -1;
    return effect_interval * 1'000'000 / cause_interval;
  }

  std::span<const std::int64_t> causes_, effects_;
  std::int64_t gap_ns_;
  static constexpr std::int64_t kLargest = std::numeric_limits<std::int64_t>::max();
  // The largest cause interval whose product with `band` (>= 0) fits 64 bits.
  static std::int64_t reach(std::int64_t band) { return band > 0 ? kLargest / band : kLargest; }

  std::int64_t low_ = 1, high_ = 0;  // the band, millionths; low_ > high_: none (too few pairs yet)
  std::vector<bool> pass_short_;     // per cause: its burst is a pass short of a multiple of the magnets
  std::int64_t low_reach_ = reach(1), high_reach_ = reach(1);  // reach(low_), reach(high_ + 1)
};

// 7.5 MAD is 5 standard deviations of a normal spread (MAD = 0.6745 sd): a true pair strays that far
// about once in two million. The floor keeps a very regular rig (sd of a few ms) from calling every
// small change a jump: a clock step of up to a few tens of ms is then still a typical latency.
constexpr std::int64_t kMinAcceptance = 50'000'000;  // ns
constexpr std::int64_t kSpreadNumerator = 15, kSpreadDenominator = 2;

// The median absolute deviation of a sorted window about its median w[size / 2]: the mid-th smallest
// (1-based, mid = size / 2) of the deviations below the median (m - w[mid - 1], m - w[mid - 2], ...,
// ascending) and above it (w[mid + 1] - m, ..., ascending), the median's own deviation left out. The
// k-th smallest of two ascending runs is the least, over the ways of taking a from the first and k - a
// from the second, of the larger of the two last taken: each split's larger one is at least the k-th
// (its k values include it), and the split of the k smallest gives it. The splits are independent of
// each other, so there is no chain of dependent choices (a merge step by step was most of this
// function's time, first as branches the data mispredicted, then as their latency).
std::int64_t sorted_window_mad(const std::int64_t* w, std::size_t size) {
  const std::size_t mid = size / 2, above_count = size - mid - 1;
  const std::int64_t median = w[mid];
  std::int64_t mad = std::numeric_limits<std::int64_t>::max();
  // a taken below (a >= 1: its last is median - w[mid - a]), mid - a above (its last w[mid + mid - a] - median).
  const std::size_t first = mid > above_count ? mid - above_count : 0;  // at most above_count above
  for (std::size_t a = first; a <= mid; ++a) {
    const std::int64_t low = a > 0 ? median - w[mid - a] : 0;
    const std::int64_t high = a < mid ? w[mid + mid - a] - median : 0;
    mad = std::min(mad, std::max(low, high));
  }
  return mid == 0 ? 0 : mad;
}

// Running median (and median absolute deviation) of the matched latencies over `k` pairs either side,
// assigned to every cause (causes without a pair take the values of the nearest pair before them, or
// the first pair; without pairs every cause takes `fallback` and kMinAcceptance): calls
// set(first, end, median, acceptance) for causes [first, end), the ranges in order and covering all
// causes. The window is kept sorted; in the middle of the recording one latency leaves it as another
// enters, and the one leaving is overwritten by moving the entering one to its place (a few steps: the
// window holds 2k + 1 values), with no vector insert or erase.
template <typename Set>
void for_each_local_reference(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
                              const std::vector<std::uint32_t>& match, int k, std::int64_t fallback,
                              Set set) {
  const auto n = static_cast<std::ptrdiff_t>(
      std::count_if(match.begin(), match.end(), [](std::uint32_t j) { return j != kNone; }));
  if (n == 0) return set(std::size_t{0}, causes.size(), fallback, kMinAcceptance);
  // The pairs are walked in `match` itself by three cursors (the pair whose median is taken, the pair
  // entering the window, the pair leaving it), so that nothing but the result and the window is
  // allocated (a list of the pairs' latencies would add 8 bytes a pair while the passes' candidates
  // are held).
  const auto next_pair = [&](std::size_t from) {  // the first matched cause >= from, or the end
    while (from < match.size() && match[from] == kNone) ++from;
    return from;
  };
  const auto latency = [&](std::size_t i) { return effects[match[i]] - causes[i]; };
  std::vector<std::int64_t> window(2 * static_cast<std::size_t>(k) + 1);
  std::int64_t* const w = window.data();
  std::size_t size = 0;
  const auto insert = [&](std::int64_t value) {
    std::size_t at = size++;
    for (; at > 0 && w[at - 1] > value; --at) w[at] = w[at - 1];
    w[at] = value;
  };
  const auto erase = [&](std::int64_t value) {
    std::size_t at = static_cast<std::size_t>(std::lower_bound(w, w + size, value) - w);
    for (--size; at < size; ++at) w[at] = w[at + 1];
  };
  // Replaces one occurrence of `old_value` by `value`, keeping the window sorted.
  const auto replace = [&](std::int64_t old_value, std::int64_t value) {
    // Its first occurrence, counted rather than searched: a binary search's steps go either way at
    // random and are mispredicted; the count is 2k + 1 compares without a branch.
    std::size_t at = 0;
    for (std::size_t t = 0; t < size; ++t) at += w[t] < old_value ? 1 : 0;
    if (value >= old_value)
      for (; at + 1 < size && w[at + 1] < value; ++at) w[at] = w[at + 1];
    else
      for (; at > 0 && w[at - 1] > value; --at) w[at] = w[at - 1];
    w[at] = value;
  };
  std::ptrdiff_t first = 0, last = 0;  // the window holds pairs [first, last)
  std::size_t entering = next_pair(0), leaving = entering, current = entering;  // their causes
  std::size_t filled = 0;                                                       // causes [0, filled) set
  for (std::ptrdiff_t p = 0; p < n; ++p) {
    const auto want_first = std::max<std::ptrdiff_t>(0, p - k),
               want_last = std::min<std::ptrdiff_t>(n, p + k + 1);
    for (; last < want_last && first < want_first; ++last, ++first) {
      replace(latency(leaving), latency(entering));
      entering = next_pair(entering + 1), leaving = next_pair(leaving + 1);
    }
    for (; last < want_last; ++last, entering = next_pair(entering + 1)) insert(latency(entering));
    for (; first < want_first; ++first, leaving = next_pair(leaving + 1)) erase(latency(leaving));
    const std::int64_t median = w[size / 2];
    const std::int64_t acceptance =
        std::max(kMinAcceptance, sorted_window_mad(w, size) * kSpreadNumerator / kSpreadDenominator);
    // Every cause up to the next pair's takes this pair's values.
    const std::size_t next = next_pair(current + 1);  // the cause of pair p + 1, or the end
    set(filled, next, median, acceptance);
    filled = next, current = next;
  }
}

// The locally typical latency and how far a true pair may stray from it, per cause (ns): the running
// median of the matched latencies, and kSpreadFactor x their median absolute deviation, at least
// kMinAcceptance (for_each_local_reference). Held in 4 bytes each where every value fits, 8 bytes a
// cause rather than 16 (pass 2's reference is held through pass 3 and both flaggings of uncertain
// pairs, beside the matches: 72 MiB at 10^7 causes rather than 143): the median as its distance from
// the global reference (within +-2.1 s; the recordings' medians lie within 0.2 s of it), the acceptance
// as it is (below 4.2 s; the recordings' reach 1.5 s). Else in 8 bytes each, built anew.
class LocalReference {
 public:
  LocalReference() = default;
  LocalReference(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
                 const std::vector<std::uint32_t>& match, int k, std::int64_t global)
      : global_(global), median_(causes.size()), acceptance_(causes.size()) {
    bool fits = true;
    // One setter for both forms: one instance of the walk, whose helpers the compiler then inlines.
    const auto set = [&](std::size_t first, std::size_t end, std::int64_t median, std::int64_t acceptance) {
      if (wide_) {
        std::fill(wide_median_.begin() + first, wide_median_.begin() + end, median);
        std::fill(wide_acceptance_.begin() + first, wide_acceptance_.begin() + end, acceptance);
        return;
      }
      const std::int64_t distance = median - global;
      // The narrow form holds a distance in [-2^31, 2^31) and an acceptance (> 0) below 2^32: one
      // unsigned compare each, without a branch.
      const auto shifted = static_cast<std::uint64_t>(distance) + 0x8000'0000u;
      fits = fits & (shifted <= 0xFFFF'FFFFu) & (static_cast<std::uint64_t>(acceptance) <= 0xFFFF'FFFFu);
      for (std::size_t i = first; i < end; ++i)
        median_[i] = static_cast<std::int32_t>(distance),
        acceptance_[i] = static_cast<std::uint32_t>(acceptance);
    };
    for_each_local_reference(causes, effects, match, k, global, set);
    if (fits) return;
    free_now(median_), free_now(acceptance_);
    wide_ = true;
    wide_median_.resize(causes.size()), wide_acceptance_.resize(causes.size());
    for_each_local_reference(causes, effects, match, k, global, set);
  }
  std::int64_t median(std::size_t i) const { return wide_ ? wide_median_[i] : global_ + median_[i]; }
  std::int64_t acceptance(std::size_t i) const { return wide_ ? wide_acceptance_[i] : acceptance_[i]; }

 private:
  bool wide_ = false;
  std::int64_t global_ = 0;                // ns
  std::vector<std::int32_t> median_;       // median - global_ (ns)
  std::vector<std::uint32_t> acceptance_;  // ns
  std::vector<std::int64_t> wide_median_;  // ns, when a value did not fit the narrow form
  std::vector<std::int64_t> wide_acceptance_;
};

// Bursts: runs of kept edges on one side closer than `gap` to the previous one. Returns the burst
// number of every edge.
std::vector<std::uint32_t> bursts(std::span<const std::int64_t> times, std::int64_t gap_ns) {
  std::vector<std::uint32_t> id(times.size(), 0);
  for (std::size_t k = 1; k < times.size(); ++k)
    id[k] = id[k - 1] + (times[k] - times[k - 1] >= gap_ns ? 1 : 0);
  return id;
}

// Marks the pairs whose assignment the data cannot make certain (PairFlag kPairAmbiguous), burst by
// burst. A sweep of the wheel passes every magnet once, so a complete burst holds a multiple of the
// magnets' count of edges, and where every edge of a burst has its partner in one burst of the other
// side, order alone fixes which edge belongs to which. A burst is doubtful when
//  - it holds an edge without partner (a pass missed on one side, or an extra edge): the order-preserving
//    rule then had a choice of which edges to leave out;
//  - its count of edges is not a multiple of the magnets: a pass was missed or an edge added on this
//    side (a pass missed on each side at different magnets leaves no edge over, but pairs the wrong
//    passes);
//  - its pairs cross a burst boundary of the other side near a boundary of its own (shifted_bursts);
//  - the spacing of its edges does not follow the other side's (broken_patterns).
// Every pair with its cause or its effect in a doubtful burst is flagged. The vehicle's wheel may turn
// slower than the operator's (down to half its speed): its bursts take a gap twice as wide, so that a
// slow sweep stays one burst.

// The two sides' bursts and which of them are doubtful.
struct BurstMarks {
  std::vector<std::uint32_t> cause, effect;  // burst number of every kept edge
  std::vector<bool> cause_bad, effect_bad;   // per burst
  void mark(std::size_t i, std::uint32_t j) { cause_bad[cause[i]] = effect_bad[effect[j]] = true; }
};

// Bursts whose count of edges is not a multiple of `magnets`.
void mark_misfits(const std::vector<std::uint32_t>& burst, std::size_t magnets, std::vector<bool>& bad) {
  for (std::size_t k = 0, first = 0; k <= burst.size(); ++k)
    if (k == burst.size() || burst[k] != burst[first]) {
      if ((k - first) % magnets != 0) bad[burst[first]] = true;
      first = k;
    }
}

// A burst boundary between consecutive pairs on one side only is a merge (two sweeps close together on
// one side) when alone, but a chain shifted by an edge when the other side has a boundary of its own
// within fewer pairs than the magnets (at least 2): the pairs between the two are marked.
void mark_shifted_bursts(const std::vector<std::uint32_t>& matched, std::size_t magnets, BurstMarks& b) {
  // The paired causes in order. Reserved to the pair count: grown by doubling, the list was up to 8
  // bytes a pair more (its old and new storage at once) at the peak of `m2mlat stats`.
  std::vector<std::uint32_t> pc;
  pc.reserve(static_cast<std::size_t>(
      std::count_if(matched.begin(), matched.end(), [](std::uint32_t j) { return j != kNone; })));
  for (std::size_t i = 0; i < matched.size(); ++i)
    if (matched[i] != kNone) pc.push_back(static_cast<std::uint32_t>(i));
  std::vector<std::ptrdiff_t> cause_only, effect_only;  // pair positions p: a boundary between p - 1 and p
  for (std::size_t p = 1; p < pc.size(); ++p) {
    const bool dc = b.cause[pc[p]] != b.cause[pc[p - 1]];
    const bool de = b.effect[matched[pc[p]]] != b.effect[matched[pc[p - 1]]];
    if (dc != de) (dc ? cause_only : effect_only).push_back(static_cast<std::ptrdiff_t>(p));
  }
  const auto reach = static_cast<std::ptrdiff_t>(std::max<std::size_t>(magnets, 2));
  std::size_t e = 0;
  for (const auto p : cause_only) {
    while (e < effect_only.size() && effect_only[e] <= p - reach) ++e;
    for (std::size_t f = e; f < effect_only.size() && effect_only[f] < p + reach; ++f)
      for (auto q = std::min(p, effect_only[f]) - 1; q <= std::max(p, effect_only[f]); ++q) {
        const auto i = pc[static_cast<std::size_t>(q)];
        b.mark(i, matched[i]);
      }
  }
}

// Within a burst, the effect edges' spacing follows the cause edges' spacing: the vehicle's wheel
// replays the operator's motion at a similar speed. Marks the bursts of two consecutive pairs (in one
// burst on each side) whose ratio (effect interval / cause interval) differs from the median ratio over
// all bursts by more than kPatternFactor: passes missed on both sides at different magnets, or a
// chain shifted inside a burst.
void mark_broken_patterns(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
                          const std::vector<std::uint32_t>& matched, BurstMarks& b) {
  // Calls `step(cause, effect, ratio)` for each pair with a pair before it in the same two bursts
  // (the later pair's edges). Walked twice, the ratio recomputed the second time (the same
  // operations give the same double), rather than kept with its pair: 16 bytes a pair and the
  // vector's doubling were a third of `m2mlat stats`'s memory at this point.
  const auto for_each_step = [&](auto&& step) {
    std::size_t prev = kNone;
    for (std::size_t i = 0; i < matched.size(); ++i) {
      if (matched[i] == kNone) continue;
      if (prev != kNone && b.cause[prev] == b.cause[i] && b.effect[matched[prev]] == b.effect[matched[i]])
        step(i, matched[i],
             static_cast<double>(effects[matched[i]] - effects[matched[prev]]) /
                 static_cast<double>(causes[i] - causes[prev]));
      prev = i;
    }
  };
  std::size_t count = 0;
  for_each_step([&](std::size_t, std::uint32_t, double) { ++count; });
  if (count == 0) return;
  std::vector<double> ratios;
  ratios.reserve(count);
  for_each_step([&](std::size_t, std::uint32_t, double ratio) { ratios.push_back(ratio); });
  const auto mid = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
  std::nth_element(ratios.begin(), mid, ratios.end());
  const double median = *mid;
  free_now(ratios);
  for_each_step([&](std::size_t cause, std::uint32_t effect, double ratio) {
    if (ratio > median * kPatternFactor || ratio < median / kPatternFactor) b.mark(cause, effect);
  });
}

std::vector<bool> ambiguous_pairs(std::span<const std::int64_t> causes, std::span<const std::int64_t> effects,
                                  const std::vector<std::uint32_t>& matched, std::int64_t gap_ns,
                                  std::size_t magnets) {
  BurstMarks b{bursts(causes, gap_ns), bursts(effects, gap_ns * kVehicleGapFactor), {}, {}};
  b.cause_bad.assign(causes.empty() ? 0 : b.cause.back() + 1, false);
  b.effect_bad.assign(effects.empty() ? 0 : b.effect.back() + 1, false);
  std::vector<bool> effect_used(effects.size(), false);
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] == kNone)
      b.cause_bad[b.cause[i]] = true;
    else
      effect_used[matched[i]] = true;
  }
  for (std::size_t j = 0; j < effects.size(); ++j)
    if (!effect_used[j]) b.effect_bad[b.effect[j]] = true;
  if (magnets > 1) {
    mark_misfits(b.cause, magnets, b.cause_bad);
    mark_misfits(b.effect, magnets, b.effect_bad);
  }
  mark_shifted_bursts(matched, magnets, b);
  mark_broken_patterns(causes, effects, matched, b);
  std::vector<bool> ambiguous(matched.size(), false);
  for (std::size_t i = 0; i < matched.size(); ++i)
    if (matched[i] != kNone) ambiguous[i] = b.cause_bad[b.cause[i]] || b.effect_bad[b.effect[matched[i]]];
  return ambiguous;
}

// The worth of a pair (units: kDeviationCost = one acceptance of deviation): kPairWorth less its
// deviation from the reference in acceptances, the deviation counted up to one acceptance. A typical
// pair is worth about 1.5, a pair beyond the acceptance 0.5. The passes compare chains by their count
// of pairs first (a typical pair counting twice), then by worth. With a tolerance given, pairs beyond
// it are not allowed at all.
constexpr std::int64_t kPairWorth = 1500, kDeviationCost = 1000;
constexpr std::size_t kConfirmingRun = 2;  // consecutive far pairs that confirm a jump (uncertain_pairs)
// A stalled link releases its queued commands together, and once they are out the link is free: the
// last pair of a confirmed jump above the reference, where its cause lies at least the burst gap after
// the one before (another manoeuvre), has its effect at most this share of that interval after the
// effect before (the queue draining). A last effect that keeps its cause's spacing is an edge after
// the drain in the place of a lost one (uncertain_pairs).
constexpr std::int64_t kDrainNumerator = 1, kDrainDenominator = 2;
// A pair next to an unconfirmed jump that would be worth at most this less (half an acceptance of
// deviation) with the jump pair's edge is flagged as competing (uncertain_pairs).
constexpr std::int64_t kNeighbourMargin = kDeviationCost / 2;
// Pass 1 knows no local spread yet: a pair within this of the global reference counts as typical.
constexpr std::int64_t kFirstPassAcceptance = 1'000'000'000;  // ns

// True when cause i at this latency lies beyond the local acceptance: not a typical pair.
bool beyond_acceptance(const LocalReference& reference, std::size_t i, std::int64_t latency) {
  const std::int64_t ref = reference.median(i);
  return (latency > ref ? latency - ref : ref - latency) >= reference.acceptance(i);
}

std::int64_t pair_worth(const LocalReference& reference, std::size_t i, std::int64_t latency,
                        std::int64_t tolerance_ns) {
  const std::int64_t ref = reference.median(i);
  const std::int64_t deviation = latency > ref ? latency - ref : ref - latency;
  if (tolerance_ns > 0 && deviation >= tolerance_ns) return kDisallowed;
  const std::int64_t acceptance = reference.acceptance(i);
  // Most candidates of a wide window lie beyond the acceptance: no division for them.
  return deviation >= acceptance ? kPairWorth - kDeviationCost
                                 : kPairWorth - deviation * kDeviationCost / acceptance;
}

// The pairs the data cannot make certain besides the bursts' (ambiguous_pairs), as PairFlag bits per
// cause:
//  - kPairCompeting: an unmatched edge could take the pair's place, alone or by shifting its
//    neighbours by one, and the pairing so changed is worth at most kDeviationCost less. (A lost edge
//    and a spurious one look the same as a real outlier and a lucky fit; one step of such a change is
//    always within that margin, so the pairs next to an unmatched edge are always flagged.)
//  - kPairJump: the latency lies beyond the local acceptance and is not confirmed by its
//    neighbours: a jump is taken as real (a stalled link) only when at least two consecutive pairs
//    jump and every edge between the typical pairs around them, on both sides, is paired, so that
//    the order alone fixes which edge belongs to which, and, above the reference, its last pair comes
//    with the queue's drain (kDrainNumerator / kDrainDenominator; `burst_gap_ns` tells manoeuvres apart).
//  - kPairCompeting also: the pair lies next to an unconfirmed jump and would fit typically, nearly as
//    well (kNeighbourMargin), with the jump pair's edge instead of its own: the jump may be a lost
//    edge's place taken by its neighbour's partner, and this pair holds a spurious edge instead.
std::vector<std::uint8_t> uncertain_pairs(const Sides& sides, const std::vector<std::uint32_t>& matched,
                                          const LocalReference& reference, std::int64_t tolerance_ns,
                                          std::int64_t burst_gap_ns) {
  // Named copies, not structured bindings: C++20 lets clang capture no binding in the lambdas below.
  const std::span<const std::int64_t> causes = sides.causes, effects = sides.effects;
  const std::int64_t min_ns = sides.min_ns, max_ns = sides.max_ns;
  static_assert(kPairUncertain < 256, "the matcher's flags fit a byte a cause");
  std::vector<std::uint8_t> flags(matched.size(), 0);
  // The pairs in order: pc[k] the cause of the k-th, pe(k) its effect, read in `matched` (a list of the
  // effects too was 4 bytes a pair more at the peak of `m2mlat stats`). Reserved to the pair count:
  // grown by doubling, the list was up to 4 bytes a pair more.
  std::vector<std::uint32_t> pc;
  const auto pair_count = static_cast<std::size_t>(
      std::count_if(matched.begin(), matched.end(), [](std::uint32_t j) { return j != kNone; }));
  pc.reserve(pair_count);
  for (std::size_t i = 0; i < matched.size(); ++i)
    if (matched[i] != kNone) pc.push_back(static_cast<std::uint32_t>(i));
  const auto pe = [&](std::size_t k) { return matched[pc[k]]; };
  const std::size_t n = pc.size();
  if (n == 0) return flags;
  const auto in_window = [&](std::uint32_t i, std::uint32_t j) {
    const std::int64_t latency = effects[j] - causes[i];
    return latency >= min_ns && latency <= max_ns;
  };
  const auto worth = [&](std::uint32_t i, std::uint32_t j) {
    return pair_worth(reference, i, effects[j] - causes[i], tolerance_ns);
  };
  const auto paired_worth = [&](std::size_t k) { return worth(pc[k], pe(k)); };
  constexpr std::size_t kMaxShift = 64;  // pairs a change may shift: far beyond what stays in the margin

  // Unmatched kept edges of each side, ascending.
  std::vector<std::uint32_t> lone_causes, lone_effects;
  {
    std::vector<bool> effect_used(effects.size(), false);
    for (const auto i : pc) effect_used[matched[i]] = true;
    for (std::size_t i = 0; i < causes.size(); ++i)
      if (matched[i] == kNone) lone_causes.push_back(static_cast<std::uint32_t>(i));
    for (std::size_t j = 0; j < effects.size(); ++j)
      if (!effect_used[j]) lone_effects.push_back(static_cast<std::uint32_t>(j));
  }
  // An unmatched edge walks into the pairs after it (step +1) or before it (step -1): at each step the
  // edge freed by the previous step takes the next pair's partner, and the change of the pairing's
  // worth adds up. The change may stop at any step (the last freed edge stays unmatched), or end by
  // pairing the freed edge with an unmatched edge of the other side that lies between this pair's
  // partner and the next one's (a pair more). Every pair up to the farthest step whose change is
  // within kDeviationCost is flagged.
  const auto walk = [&](std::ptrdiff_t k, int step, std::uint32_t free, bool free_is_cause) {
    const auto& others = free_is_cause ? lone_effects : lone_causes;
    const auto partner = [&](std::size_t q) { return free_is_cause ? pe(q) : pc[q]; };
    const auto own = [&](std::size_t q) { return free_is_cause ? pc[q] : pe(q); };
    const auto make = [&](std::uint32_t mine, std::uint32_t other) {  // (cause, effect)
      return free_is_cause ? std::pair{mine, other} : std::pair{other, mine};
    };
    const auto value = [&](std::uint32_t mine, std::uint32_t other) {
      const auto [i, j] = make(mine, other);
      return in_window(i, j) ? worth(i, j) : kDisallowed;
    };
    const std::ptrdiff_t start = k;
    std::int64_t change = 0;
    std::ptrdiff_t flag_to = -1;  // the farthest step within the margin
    std::ptrdiff_t steps = 0;
    for (; steps < static_cast<std::ptrdiff_t>(kMaxShift) && k >= 0 && static_cast<std::size_t>(k) < n;
         ++steps, k += step) {
      const auto q = static_cast<std::size_t>(k);
      const std::int64_t w = value(free, partner(q));
      if (w == kDisallowed) break;
      change += w - paired_worth(q);
      free = own(q);
      if (change >= -kDeviationCost) flag_to = steps;
      // End with an unmatched edge of the other side between partner(q) and the next pair's partner.
      const bool forward = step > 0;
      const auto first = forward ? std::upper_bound(others.begin(), others.end(), partner(q))
                         : q > 0 ? std::upper_bound(others.begin(), others.end(), partner(q - 1))
                                 : others.begin();
      const std::uint32_t below = forward ? (q + 1 < n ? partner(q + 1) : kNone) : partner(q);
      for (auto it = first; it != others.end() && *it < below; ++it) {
        const std::int64_t end = value(free, *it);
        if (end != kDisallowed && change + end >= -kDeviationCost) flag_to = steps;
      }
      if (change < -kDeviationCost - kPairWorth) break;  // no ending can bring it back
    }
    for (std::ptrdiff_t r = 0; r <= flag_to; ++r) flags[pc[static_cast<std::size_t>(start + r * step)]] |= kPairCompeting;
  };
  for (const auto i : lone_causes) {
    const auto next = static_cast<std::ptrdiff_t>(std::lower_bound(pc.begin(), pc.end(), i) - pc.begin());
    walk(next, +1, i, true);
    walk(next - 1, -1, i, true);
  }
  for (const auto j : lone_effects) {
    // The first pair whose effect is >= j (the pairs' effects ascend with their causes).
    const auto next = static_cast<std::ptrdiff_t>(
        std::lower_bound(pc.begin(), pc.end(), j,
                         [&](std::uint32_t i, std::uint32_t e) { return matched[i] < e; }) -
        pc.begin());
    walk(next, +1, j, false);
    walk(next - 1, -1, j, false);
  }

  // Jumps: runs of consecutive pairs beyond the acceptance.
  const auto jumps = [&](std::size_t k) {
    return beyond_acceptance(reference, pc[k], effects[pe(k)] - causes[pc[k]]);
  };
  for (std::size_t k = 0; k < n;) {
    if (!jumps(k)) {
      ++k;
      continue;
    }
    std::size_t end = k;
    while (end < n && jumps(end)) ++end;
    // Confirmed: two or more, typical pairs on both sides, every edge between those paired, and not a
    // chain shifted by one edge: if each cause of the run fits typically with its neighbour's
    // partner, the run is as likely a shifted chain that swallowed an unmatched edge at either end.
    bool confirmed = end - k >= kConfirmingRun && k > 0 && end < n && pc[end] - pc[k - 1] == end - k + 1 &&
                     pe(end) - pe(k - 1) == end - k + 1;
    // A real change of latency moves it one way (a stall holds commands back; a handover to a faster
    // link shortens them): a run that lies partly below and partly above the reference is a chain
    // that took a wrong edge.
    {
      const auto above = [&](std::size_t r) {
        return effects[pe(r)] - causes[pc[r]] > reference.median(pc[r]);
      };
      for (std::size_t r = k + 1; r < end; ++r)
        if (above(r) != above(k)) confirmed = false;
    }
    for (const int shift : {-1, +1}) {
      std::size_t fits = 0;
      for (std::size_t r = k; r < end; ++r) {
        const auto q = static_cast<std::ptrdiff_t>(r) + shift;
        if (q < 0 || static_cast<std::size_t>(q) >= n) continue;
        const std::uint32_t i = pc[r], j = pe(static_cast<std::size_t>(q));
        fits += !beyond_acceptance(reference, i, effects[j] - causes[i]);
      }
      if (2 * fits >= end - k) confirmed = false;
    }
    // Above the reference a confirmed jump is a stall: its last pair comes with the queue's drain.
    if (confirmed) {
      const std::size_t r = end - 1;  // > k: a confirmed run holds kConfirmingRun pairs or more
      const std::int64_t cause_step = causes[pc[r]] - causes[pc[r - 1]];
      const std::int64_t effect_step = effects[pe(r)] - effects[pe(r - 1)];
      if (cause_step >= burst_gap_ns && effects[pe(r)] - causes[pc[r]] > reference.median(pc[r]) &&
          effect_step * kDrainDenominator > cause_step * kDrainNumerator)
        confirmed = false;
    }
    if (!confirmed)
      for (std::size_t r = k; r < end; ++r) flags[pc[r]] |= kPairJump;
    k = end;
  }
  // The neighbours of unconfirmed jumps. A pair that would fit typically, nearly as well, with the jump
  // pair's edge instead of its own may have given its true partner away: a cause whose effect was lost
  // took the next cause's effect (far), and that cause a spurious effect (typical); or a spurious cause
  // just before a true one took its effect, and the true cause the next effect (far).
  for (std::size_t r = 0; r < n; ++r) {
    if ((flags[pc[r]] & kPairJump) == 0) continue;
    for (const std::size_t q : {r - 1, r + 1}) {  // r - 1 wraps to above n at r = 0
      if (q >= n || (flags[pc[q]] & kPairJump) != 0) continue;
      const std::int64_t now = paired_worth(q);
      const auto nearly_as_good = [&](std::uint32_t i, std::uint32_t j) {
        return in_window(i, j) && !beyond_acceptance(reference, i, effects[j] - causes[i]) &&
               worth(i, j) >= now - kNeighbourMargin;
      };
      if (nearly_as_good(pc[r], pe(q)) || nearly_as_good(pc[q], pe(r))) flags[pc[q]] |= kPairCompeting;
    }
  }
  return flags;
}

// How long after the kept edge at input index `kept` the edges dropped as its bounces go on (ns; 0
// without bounces). The refractory filter keeps the first edge of a cluster: right for contact bounce,
// which follows the true edge, but a spurious edge just before the true one makes the true one a
// "bounce". The pass's edge is then somewhere in the cluster. The pairs ask in the order of their
// edges, so a cursor walks the bounces along (no search per pair).
class BounceSpan {
 public:
  BounceSpan(std::span<const std::int64_t> times, const std::vector<std::int64_t>& bounces)
      : times_(times), bounces_(bounces) {}
  // `kept` must not decrease from one call to the next.
  std::int64_t operator()(std::int64_t kept) {
    while (next_ < bounces_.size() && bounces_[next_] <= kept) ++next_;
    std::int64_t last = kept;
    for (; next_ < bounces_.size() && bounces_[next_] == last + 1; ++next_) last = bounces_[next_];
    return times_[static_cast<std::size_t>(last)] - times_[static_cast<std::size_t>(kept)];
  }

 private:
  std::span<const std::int64_t> times_;
  const std::vector<std::int64_t>& bounces_;
  std::size_t next_ = 0;  // the first bounce after the last edge asked for
};

// One cause's rule in an alignment pass (align): the worth of its candidates (pair_worth, with the
// reference and acceptance of this cause), the count of a pair by its worth (typical or not), and its
// sweep link.
constexpr std::int64_t kLooseWorth = kPairWorth - kDeviationCost;  // the worth of a pair beyond the acceptance
struct PassRow {
  std::int64_t reference, acceptance, tolerance_ns;
  std::uint32_t typical_count, far_count;  // the count of a pair worth more than kLooseWorth, of the others
  SweepStretch::Link follows;
  std::int64_t value(std::int64_t latency) const {
    const std::int64_t deviation = latency > reference ? latency - reference : reference - latency;
    if (tolerance_ns > 0 && deviation >= tolerance_ns) return kDisallowed;
    return deviation >= acceptance ? kLooseWorth : kPairWorth - deviation * kDeviationCost / acceptance;
  }
  std::uint32_t count(std::int64_t v) const { return v > kLooseWorth ? typical_count : far_count; }
};

// Runs align with the narrowest key that holds every chain's (count, value): at most min(causes,
// effects) pairs, each of count <= 3 and value <= kPairWorth.
template <typename RowOf>
std::vector<std::uint32_t> align_pass(const Sides& sides, const CandidateCount& count, ChainBlocks& chains,
                                      RowOf row_of) {
  const auto pairs = static_cast<std::uint64_t>(std::min(sides.causes.size(), sides.effects.size()));
  const auto shift = static_cast<unsigned>(std::bit_width(pairs * kPairWorth));
  if (std::bit_width(3 * pairs) + shift <= 64) return align<std::uint64_t>(sides, count, chains, shift, row_of);
  return align<WideKey>(sides, count, chains, 64, row_of);
}

void check_sorted(std::span<const std::int64_t> times, const char* side) {
  const auto it = std::is_sorted_until(times.begin(), times.end());
  if (it != times.end())
    throw core::Error(core::ErrorKind::data, fmt::format("{} timestamps are not in time order (at index {})",
                                                         side, it - times.begin()));
}

}  // namespace

core::Duration burst_gap_of(const MatchOptions& options) {
  return options.burst_gap.count() > 0 ? options.burst_gap : burst_gap_for(options.magnets_deg);
}

core::Duration burst_gap_for(std::span<const double> magnets_deg) {
  std::vector<double> angles(magnets_deg.begin(), magnets_deg.end());
  std::sort(angles.begin(), angles.end());
  double widest = 0;  // degrees between neighbouring magnets (a sweep turns across, not around)
  for (std::size_t k = 1; k < angles.size(); ++k) widest = std::max(widest, angles[k] - angles[k - 1]);
  const auto gap = core::Duration{static_cast<std::int64_t>(widest / kSlowestSteeringDegPerS * 1e9)};
  return std::max(gap, kDefaultBurstGap);
}

MatchResult match(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                  core::Clock clock, const MatchOptions& options) {
  // Copies the matcher may rearrange (8 bytes an edge a side): a caller that owns its columns saves
  // them with match_in_place.
  std::vector<std::int64_t> causes(cause_ns.begin(), cause_ns.end()),
      effects(effect_ns.begin(), effect_ns.end());
  return match_in_place(causes, effects, clock, options);
}

namespace {
void rule_match(const Sides& sides, const CandidateCount& counted, const Kept& causes, const Kept& effects,
                std::size_t candidate_total, const MatchOptions& options, std::vector<std::uint32_t>& matched_out,
                std::vector<std::uint8_t>& flags_out);
void finish_match(MatchResult& result, const Sides& sides, Kept& causes, Kept& effects,
                  std::span<std::int64_t> cause_ns, std::span<std::int64_t> effect_ns,
                  std::vector<std::uint32_t>& matched, std::vector<std::uint8_t>& flags);
}  // namespace

MatchResult match_in_place(std::span<std::int64_t> cause_ns, std::span<std::int64_t> effect_ns,
                           core::Clock clock, const MatchOptions& options) {
  if (options.max_latency <= options.min_latency)
    throw core::Error(core::ErrorKind::usage,
                      "the latency window is empty: max latency must exceed min latency");
  if (options.tolerance.count() < 0)
    throw core::Error(core::ErrorKind::usage, "the tolerance must not be negative (0: none)");
  if (options.reference_neighbours < 1)
    throw core::Error(core::ErrorKind::usage, "reference neighbours must be >= 1");
  if (options.min_latency < -kMaxLatency || options.max_latency > kMaxLatency)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("the latency window {} .. {} reaches beyond the matcher's limit of +-{}",
                    core::format_duration(options.min_latency), core::format_duration(options.max_latency),
                    core::format_duration(kMaxLatency)));
  if (cause_ns.size() >= kMaxEvents || effect_ns.size() >= kMaxEvents)
    throw core::Error(core::ErrorKind::usage, "more than 2 billion events on one side: split the input");
  check_sorted(cause_ns, "cause");
  check_sorted(effect_ns, "effect");

  Kept causes(cause_ns, options.refractory);
  Kept effects(effect_ns, options.refractory);
  const Sides sides{causes.ns, effects.ns, options.min_latency.count(), options.max_latency.count()};
  const std::int64_t min_ns = sides.min_ns, max_ns = sides.max_ns;
  // Memory follows the number of candidate pairs where the chains do not meet (5 to 8 bytes each in the
  // passes, ChainBlocks): refuse a window that holds more than the limit before anything is allocated.
  const CandidateCount counted = candidate_count(sides);
  const std::size_t candidate_total = counted.total;
  if (candidate_total > kMaxCandidates)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("the latency window {} .. {} holds {} candidate pairs, more than the "
                    "matcher's limit of {}: narrow the window",
                    core::format_duration(options.min_latency), core::format_duration(options.max_latency),
                    candidate_total, kMaxCandidates));

  MatchResult result;
  result.clock = clock;
  result.cause_count = static_cast<std::int64_t>(cause_ns.size());
  result.effect_count = static_cast<std::int64_t>(effect_ns.size());
  result.burst_gap = burst_gap_of(options);
  std::vector<std::uint32_t> matched;
  std::vector<std::uint8_t> flags;
  std::vector<float> probability;  // per kept cause, with the model
  if (options.method == MatchOptions::Method::model) {
    if (!(options.min_probability > 0 && options.min_probability < 1))
      throw core::Error(core::ErrorKind::usage, "the minimum probability must lie in (0, 1)");
    if (candidate_total > kMaxModelCandidates)
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("the latency window {} .. {} holds {} candidate pairs, more than the alignment "
                                    "model's limit of {}: narrow the window, or pair with --matcher rules",
                                    core::format_duration(options.min_latency),
                                    core::format_duration(options.max_latency), candidate_total, kMaxModelCandidates));
    auto m = model_match(causes.ns, effects.ns, min_ns, max_ns, options.min_probability);
    matched = std::move(m.matched);
    flags = std::move(m.flags);
    probability = std::move(m.probability);
    result.model = m.summary;
  } else {
    rule_match(sides, counted, causes, effects, candidate_total, options, matched, flags);
  }
  finish_match(result, sides, causes, effects, cause_ns, effect_ns, matched, flags);
  // The pairs are the matched kept causes in order: their probabilities in the same order.
  if (!probability.empty()) {
    result.probability.reserve(result.pairs.size());
    for (std::size_t i = 0; i < matched.size(); ++i)
      if (matched[i] != kNone) result.probability.push_back(probability[i]);
  }
  return result;
}

namespace {

// The rules' passes (docs/matcher.md, "The rule"): the matches and their flags per kept cause.
void rule_match(const Sides& sides, const CandidateCount& counted, const Kept& causes, const Kept& effects,
                std::size_t candidate_total, const MatchOptions& options, std::vector<std::uint32_t>& matched_out,
                std::vector<std::uint8_t>& flags_out) {
  // Pass 1: one global reference; every candidate in the window is allowed, and the best fit wins.
  const std::int64_t global = global_reference(sides, candidate_total);
  ChainBlocks chains;
  LocalReference reference;  // of the pass before
  const std::int64_t tolerance = options.tolerance.count();
  auto matched = align_pass(sides, counted, chains, [&](std::size_t) {
    return PassRow{global, kFirstPassAcceptance, tolerance, 0, 0, {}};
  });
  // Pass 2: against the local reference of pass 1; the most pairs (a typical one counting twice), then
  // the largest worth. (A third such pass, against pass 2's reference, changed nothing measurable.)
  // Each pass's matches go once what it needs of them is taken (the sweep's band, the reference):
  // the pass after writes its own (4 bytes a cause each).
  const auto gap = burst_gap_of(options);
  const std::size_t magnet_count = std::max<std::size_t>(1, options.magnets_deg.size());
  SweepStretch sweep(causes.ns, effects.ns, gap.count(), magnet_count);
  sweep.fit(matched);
  reference = LocalReference(causes.ns, effects.ns, matched, options.reference_neighbours, global);
  free_now(matched);
  matched = align_pass(sides, counted, chains, [&](std::size_t i) {
    return PassRow{reference.median(i), reference.acceptance(i), tolerance, 2, 1, sweep.link(i)};
  });
  // Pass 1's reference goes before the sweep's band is fitted and pass 2's reference built: the two
  // references at once made one of the plateaus of `m2mlat stats` as high as its peak.
  reference = LocalReference();
  sweep.fit(matched);
  reference = LocalReference(causes.ns, effects.ns, matched, options.reference_neighbours, global);
  // Pass 3: a pair far from the typical latency that an unmatched edge could replace counts nothing
  // (only its worth), so that such pairs never displace a typical one: a lost edge and a spurious one
  // must not push a true pair out.
  {
    std::vector<bool> demoted(matched.size(), false);
    {  // the flags (a byte a cause) go before the pass
      const auto doubtful = uncertain_pairs(sides, matched, reference, tolerance, gap.count());
      for (std::size_t i = 0; i < matched.size(); ++i)
        demoted[i] = matched[i] != kNone && (doubtful[i] & kPairCompeting) != 0 &&
                     beyond_acceptance(reference, i, effects.ns[matched[i]] - causes.ns[i]);
    }
    free_now(matched);
    matched = align_pass(sides, counted, chains, [&](std::size_t i) {
      return PassRow{reference.median(i), reference.acceptance(i), tolerance, 2, demoted[i] ? 0u : 1u,
                     sweep.link(i)};
    });
  }
  chains = ChainBlocks();

  auto flags = uncertain_pairs(sides, matched, reference, options.tolerance.count(), gap.count());
  reference = LocalReference();
  {
    const auto ambiguous = ambiguous_pairs(causes.ns, effects.ns, matched, gap.count(),
                                           std::max<std::size_t>(1, options.magnets_deg.size()));
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (ambiguous[i]) flags[i] |= kPairAmbiguous;
  }
  matched_out = std::move(matched);
  flags_out = std::move(flags);
}

// The unmatched edges with their reasons and the pairs with their bounce spans, in input indices;
// puts both columns back.
void finish_match(MatchResult& result, const Sides& sides, Kept& causes, Kept& effects,
                  std::span<std::int64_t> cause_ns, std::span<std::int64_t> effect_ns,
                  std::vector<std::uint32_t>& matched, std::vector<std::uint8_t>& flags) {
  const std::int64_t min_ns = sides.min_ns, max_ns = sides.max_ns;

  // Reasons for everything left over, first: they need the kept timestamps (a cause's window, an
  // effect's candidates), which then go back to their input indices before the pairs are built.
  std::vector<bool> effect_used(effects.ns.size(), false);
  std::size_t pair_count = 0;
  for (const auto j : matched)
    if (j != kNone) effect_used[j] = true, ++pair_count;
  // Each side's unpaired kept edges come in input order, and so do its bounces: merging the two
  // gives the list sorted by side, then index, without a sort.
  result.unmatched.reserve(causes.ns.size() + effects.ns.size() - 2 * pair_count + causes.bounces.size() +
                           effects.bounces.size());
  std::size_t bounce = 0;  // the next bounce of the side being listed
  // Lists the side's bounces before input index `below`, then (unless it is kAllBounces) the edge itself.
  // (Input indices are below kMaxEvents, 2^31, checked above: they fit the list's 32 bits.)
  auto add = [&](Side side, std::int64_t below, UnmatchedReason reason,
                 const std::vector<std::int64_t>& bounces) {
    for (; bounce < bounces.size() && bounces[bounce] < below; ++bounce)
      result.unmatched.push_back(
          Unmatched{static_cast<std::uint32_t>(bounces[bounce]), side, UnmatchedReason::bounce});
    if (below != kAllBounces)
      result.unmatched.push_back(Unmatched{static_cast<std::uint32_t>(below), side, reason});
  };
  {
    KeptIndex cause_index(causes.bounces);
    Window w = sides.window();
    for (std::size_t i = 0; i < matched.size(); ++i) {
      if (matched[i] != kNone) continue;
      w.at(i);
      add(Side::cause, cause_index(i),
          w.lo == w.hi ? UnmatchedReason::no_candidate : UnmatchedReason::outmatched, causes.bounces);
    }
    add(Side::cause, kAllBounces, UnmatchedReason::bounce, causes.bounces);
  }
  bounce = 0;
  {
    KeptIndex effect_index(effects.bounces);
    for (std::size_t j = 0; j < effects.ns.size(); ++j) {
      if (effect_used[j]) continue;
      // A cause in [effect - max, effect - min] would have had this effect as a candidate.
      const auto first = std::lower_bound(causes.ns.begin(), causes.ns.end(), effects.ns[j] - max_ns);
      const bool candidate = first != causes.ns.end() && *first <= effects.ns[j] - min_ns;
      add(Side::effect, effect_index(j),
          candidate ? UnmatchedReason::outmatched : UnmatchedReason::no_candidate, effects.bounces);
    }
    add(Side::effect, kAllBounces, UnmatchedReason::bounce, effects.bounces);
  }
  free_now(effect_used);
  causes.restore();
  effects.restore();

  // The pairs (16 bytes each, the largest part of the result), in cause order and so in effect order.
  result.pairs.reserve(pair_count);
  KeptIndex cause_index(causes.bounces), effect_index(effects.bounces);
  BounceSpan cause_bounce_span(cause_ns, causes.bounces), effect_bounce_span(effect_ns, effects.bounces);
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (matched[i] == kNone) continue;
    const auto c = cause_index(i), e = effect_index(matched[i]);
    const std::int64_t cause_span = cause_bounce_span(c), effect_span = effect_bounce_span(e);
    const bool bounced = cause_span > kBounceSpanLimit.count() || effect_span > kBounceSpanLimit.count();
    // Indices below kMaxEvents (2^31, checked above): they fit the pair's 32 bits.
    result.pairs.push_back(Pair{static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(e),
                                flags[i] | (bounced ? kPairBounced : 0u),
                                static_cast<std::int32_t>(std::min<std::int64_t>(
                                    cause_span + effect_span, std::numeric_limits<std::int32_t>::max()))});
  }
}

}  // namespace

MatchResult match(std::span<const core::Event> causes, std::span<const core::Event> effects,
                  const MatchOptions& options) {
  std::vector<std::int64_t> cause_ns, effect_ns;
  cause_ns.reserve(causes.size());
  effect_ns.reserve(effects.size());
  const core::Clock clock = !causes.empty()    ? causes.front().time.clock()
                            : !effects.empty() ? effects.front().time.clock()
                                               : core::Clock::realtime;
  for (const auto& [events, out] : {std::pair{causes, &cause_ns}, std::pair{effects, &effect_ns}})
    for (const auto& event : events) {
      if (event.time.clock() != clock)
        throw core::Error(core::ErrorKind::data,
                          fmt::format("cannot pair a {} timestamp with a {} timestamp (event on {}/{})",
                                      core::to_string(event.time.clock()), core::to_string(clock), event.node,
                                      event.channel));
      out->push_back(event.time.ns());
    }
  return match_in_place(cause_ns, effect_ns, clock, options);
}

}  // namespace m2mlat::pairing
