// The candidate lattice of the alignment model (alignment_model.hpp): every cause edge with every
// effect edge in its latency window. Forward-backward (sums) gives each candidate pair's posterior
// probability, Viterbi (maxima over the same lattice) the most probable alignment.
//
// A pair's predecessors are every earlier pair (a cause and an effect before it both), so that any
// run of unmatched edges is possible; those at most max_skip edges of either side back are linked
// (their latency's density depends on the predecessor's), the others are not (the fresh draw only),
// and the sums over them factor: (cause_loss)^(causes between) x (unmatched_per_s)^(effects between)
// x the predecessor's score, kept per effect column and folded into one running sum for the columns
// behind every later window, so each candidate costs O(max_skip^2) whatever the run. Everything is
// in log space.
#pragma once

#include <cstddef>
#include <cstdint>
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
  // Both sides sorted by time, ns.
  AlignmentLattice(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                   const AlignmentModel& model);

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
  void forward(bool maximum);
  void backward();

  AlignmentModel model_;
  std::vector<double> cause_s_, effect_s_;  // times relative to the first edge, s
  std::vector<std::size_t> lo_, hi_, offset_;
  std::vector<double> latency_;  // per candidate, s
  std::vector<double> alpha_, beta_, viterbi_;
  std::vector<std::int64_t> back_;  // per candidate: the Viterbi predecessor's index, -1 for none
  double log_z_ = 0;
  AlignmentResult best_;
};

}  // namespace m2mlat::pairing
