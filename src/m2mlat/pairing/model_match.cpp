// The fitted alignment as the matcher's matches and flags (model_match.hpp).
#include "m2mlat/pairing/model_match.hpp"

#include "m2mlat/pairing/alignment_fit.hpp"
#include "m2mlat/pairing/chain_blocks.hpp"
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::pairing {

ModelMatch model_match(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                       std::int64_t min_latency_ns, std::int64_t max_latency_ns, double min_probability) {
  AlignmentFitOptions options;
  options.min_latency_s = static_cast<double>(min_latency_ns) * 1e-9;
  options.max_latency_s = static_cast<double>(max_latency_ns) * 1e-9;
  const auto fit = fit_alignment(cause_ns, effect_ns, options);
  ModelMatch out;
  out.matched.assign(cause_ns.size(), kNoCandidate);
  out.flags.assign(cause_ns.size(), 0);
  out.probability.assign(cause_ns.size(), 0.0f);
  out.summary.parameters = fit.model;
  out.summary.iterations = fit.iterations;
  out.summary.min_probability = min_probability;
  const auto& a = fit.alignment;
  for (std::size_t k = 0; k < a.pairs.size(); ++k) {
    const auto [i, j] = a.pairs[k];
    out.matched[i] = static_cast<std::uint32_t>(j);
    out.probability[i] = static_cast<float>(a.probability[k]);
    if (a.probability[k] < min_probability) {
      out.flags[i] = kPairImprobable;
    } else {
      ++out.summary.kept;
      out.summary.expected_wrong += 1 - a.probability[k];
    }
  }
  return out;
}

}  // namespace m2mlat::pairing
