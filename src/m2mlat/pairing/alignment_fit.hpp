// The alignment model's parameters from the log itself (hard EM, Viterbi training): align with the
// current parameters, re-estimate them from that alignment, until the alignment no longer changes.
// From the alignment's pairs: cause_loss = causes unmatched / causes; unmatched_per_s = effects
// unmatched / the log's span; mean_s and spread_s the latencies' median and 1.4826 x MAD; jitter_s,
// stretch, stretch_sd, tau_s, reset, sweep and sweep_sd the maximum likelihood of the pairs'
// latencies (coordinate search on logarithmic grids, twice over). The start: mean_s at the
// densest 50 ms of every candidate latency (true pairs pile up at the typical latency, wrong ones
// spread over the window), the rest broad. A long log is narrowed (AlignmentFitOptions::exact_candidates).
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
  // Up to this many candidate pairs every one is scored; beyond, the parameters come from the first
  // causes' this many, and each cause's candidates lie within band_spreads times the level's spread
  // (at least min_band_s) of the level, except about a cause that band leaves unmatched or
  // improbable (p < 0.99), where the whole window is searched.
  std::size_t exact_candidates = 50'000;
  double band_spreads = 8;
  double min_band_s = 0.25;
};

struct FittedAlignment {
  AlignmentModel model;  // the parameters the alignment below was made with
  AlignmentResult alignment;
  int iterations = 0;
};

FittedAlignment fit_alignment(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                              const AlignmentFitOptions& options = {});

}  // namespace m2mlat::pairing
