// Collects a streamed run into vectors: see simulate.hpp.
#include "m2mlat/sim/simulate.hpp"

#include <memory>

namespace m2mlat::sim {

namespace {
template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}
}  // namespace

Simulation simulate(const RigConfig& config) {
  Simulation run;
  auto generator = std::make_unique<Generator>(config);
  run.config = generator->config();
  Chunk chunk;
  while (generator->next(chunk)) {
    append(run.cause_events, chunk.cause_events);
    append(run.effect_events, chunk.effect_events);
    append(run.cause_truth, chunk.cause_truth);
    append(run.effect_truth, chunk.effect_truth);
    append(run.passes, chunk.passes);
    append(run.pairs, chunk.pairs);
    append(run.manoeuvres, chunk.manoeuvres);
    append(run.clock_samples, chunk.clock_samples);
  }
  return run;
}

}  // namespace m2mlat::sim
