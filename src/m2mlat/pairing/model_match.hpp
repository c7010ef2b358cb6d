// The alignment model as the matcher's method (`--matcher model`, docs/matcher.md "Pairing as
// inference"): the model fitted to the log (alignment_fit.hpp), its most probable alignment, and a
// pair whose posterior probability is below min_probability flagged kPairImprobable (left out of the
// statistics). Works on the kept edges (the refractory filter's), as the rules do.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/pairing/alignment_model.hpp"

namespace m2mlat::pairing {

// What the model says of a match: its fitted parameters, and of the pairs kept (p >= the level) how
// many, and how many of them are expected to be wrong (the sum of 1 - p).
struct ModelSummary {
  AlignmentModel parameters;
  int iterations = 0;
  double min_probability = 0.99;
  std::size_t kept = 0;
  double expected_wrong = 0;
};

struct ModelMatch {
  std::vector<std::uint32_t> matched;  // per kept cause: its kept effect's index, or kNoCandidate
  std::vector<std::uint8_t> flags;     // per kept cause: kPairImprobable where p < min_probability
  std::vector<float> probability;      // per kept cause: its pair's posterior probability (0 unpaired)
  ModelSummary summary;
};

ModelMatch model_match(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                       std::int64_t min_latency_ns, std::int64_t max_latency_ns, double min_probability);

}  // namespace m2mlat::pairing
