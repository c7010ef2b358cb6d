// The alignment model's parameters from the log itself (hard EM, Viterbi training): align with the
// current parameters, re-estimate them from that alignment, until the alignment no longer changes.
// From the alignment's pairs: cause_loss = causes unmatched / causes; unmatched_per_s = effects
// unmatched / the log's span; mean_s and spread_s the latencies' median and 1.4826 x MAD; jitter_s,
// stretch, stretch_sd, tau_s, reset, sweep and sweep_sd the maximum likelihood of the first 4000
// pairs' latencies (a coordinate search on logarithmic grids, one pass a round). The start: mean_s at the
// densest 50 ms of every candidate latency (true pairs pile up at the typical latency, wrong ones
// spread over the window), the rest broad.
#pragma once

#include <cstdint>
#include <span>

#include "m2mlat/pairing/alignment_lattice.hpp"
#include "m2mlat/pairing/alignment_model.hpp"

namespace m2mlat::pairing {

struct AlignmentFitOptions {
  double min_latency_s = 0, max_latency_s = 10;  // the candidates' window
  std::size_t max_skip = 2;
  int max_iterations = 8;
};

struct FittedAlignment {
  AlignmentModel model;  // the parameters the alignment below was made with
  AlignmentResult alignment;
  int iterations = 0;
};

FittedAlignment fit_alignment(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                              const AlignmentFitOptions& options = {});

}  // namespace m2mlat::pairing
