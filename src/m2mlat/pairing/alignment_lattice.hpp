// The candidate lattice of the alignment model (alignment_model.hpp): every cause edge with every
// effect edge in its latency window. Forward-backward (sums) gives each candidate pair's posterior
// probability, Viterbi (maxima over the same lattice) the most probable alignment.
//
// A candidate has states: "afresh" (a first pair, or its latency drawn afresh) and one per linked
// predecessor (an earlier candidate at most max_skip edges of either side back), which carries the
// link's stretch on to the next pair. A pair drawn afresh may follow any earlier pair (any run of
// unmatched edges): those sums factor, (cause_loss)^(causes between) x (unmatched_per_s)^(effects
// between) x the predecessor's total, kept per effect column and folded into one running sum for the
// columns behind every later window. A candidate costs O((max_skip + 1)^4) operations (its linked
// predecessors' states), whatever the runs. Everything is in log space.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "m2mlat/pairing/alignment_model.hpp"

namespace m2mlat::pairing {

struct AlignmentResult {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (cause, effect) indices, in order
  std::vector<double> probability;                         // per pair: its posterior probability
  double log_score = 0;                                    // the alignment's log score
};

class AlignmentLattice {
 public:
  // Both sides sorted by time, ns. Without posteriors only the best alignment is computed (its
  // probabilities and the evidence are then NaN): a third of the work, for the fit's rounds.
  AlignmentLattice(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                   const AlignmentModel& model, bool posteriors = true);
  std::size_t candidates() const { return latency_.size(); }

  // The effects in cause i's window: [first, last).
  std::pair<std::size_t, std::size_t> window(std::size_t cause) const { return {lo_[cause], hi_[cause]}; }
  // The posterior probability that cause i and effect j are a pair (0 outside the window).
  double posterior(std::size_t cause, std::size_t effect) const;
  // log of the sum of every alignment's score.
  double log_evidence() const { return log_z_; }
  // The most probable alignment, each pair with its posterior.
  const AlignmentResult& best() const { return best_; }

 private:
  std::size_t index(std::size_t cause, std::size_t effect) const { return offset_[cause] + (effect - lo_[cause]); }
  std::size_t slots(std::size_t k) const { return 1 + pred_begin_[k + 1] - pred_begin_[k]; }
  std::size_t slot(std::size_t k, std::size_t s) const { return k + pred_begin_[k] + s; }
  // The stretch a state carries on: its link's effect interval over its cause interval (none afresh).
  std::optional<double> stretch(std::size_t k, std::size_t s) const;
  double start(std::size_t k) const;  // the first pair's terms: the edges before it unmatched, its level
  double end(std::size_t k) const;    // the edges after the last pair unmatched
  void forward(bool maximum);
  void backward();

  AlignmentModel model_;
  bool posteriors_ = true;
  double log_loss_ = 0, log_kept_ = 0, log_unmatched_ = 0, fresh_ = 0;
  double log_keep_ = 0, log_sweep_ = 0, log_level_ = 0;  // log(1 - reset), log sweep, log(1 - sweep)
  double mix(double sweep, double level) const;  // log(sweep e^sweep + (1 - sweep) e^level)
  std::vector<double> cause_s_, effect_s_;  // times relative to the first edge, s
  std::vector<std::size_t> lo_, hi_, offset_;
  std::vector<std::uint32_t> cause_, effect_;  // per candidate
  std::vector<double> latency_;                // per candidate, s
  // Linked predecessors: candidate k's are pred_[pred_begin_[k] .. pred_begin_[k + 1]), each with the
  // log of its unmatched edges' factors; succ_ lists, per candidate, the indices into pred_ naming it.
  std::vector<std::size_t> pred_begin_, pred_, pred_owner_, succ_begin_, succ_;
  std::vector<double> pred_skip_;
  // Per link (index into pred_): the level's part of its latency's density, its cause interval, its
  // stretch (effect interval / cause interval), and the sweep part's variance and normalisation.
  std::vector<double> link_level_, link_dc_, link_stretch_, link_sweep_var_, link_sweep_norm_;
  double sweep_part(std::size_t q, double carried) const;  // log_sweep_link of link q
  std::vector<double> alpha_, beta_, viterbi_;  // per state (slot)
  std::vector<std::int64_t> back_;               // per state: the Viterbi predecessor's state, -1 for none
  double log_z_ = 0;
  AlignmentResult best_;
};

}  // namespace m2mlat::pairing
