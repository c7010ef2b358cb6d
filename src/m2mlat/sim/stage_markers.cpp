#include "m2mlat/sim/stage_markers.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/clock_model.hpp"
#include "m2mlat/sim/random.hpp"

namespace m2mlat::sim {

namespace {

// Streams of their own, so that the stages never move the run's other draws.
constexpr std::uint64_t kStageStreams = 0x7374'0000;  // "st"
// The send stage: socket to wire, uniform in [50, 400) us, never more than the command delay.
constexpr std::int64_t kSendMinNs = 50'000;
constexpr std::int64_t kSendMaxNs = 400'000;

}  // namespace

StageMarkers stage_markers(const Simulation& run, const StageMarkerOptions& options) {
  if (!(options.drop_probability >= 0 && options.drop_probability <= 1))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("markers' drop probability {} is not in [0, 1]", options.drop_probability));
  const auto& config = run.config;
  Rng send_rng(config.seed, kStageStreams + 1);
  Rng drop_rng(config.seed, kStageStreams + 2);
  StageMarkers out;
  out.chains.reserve(run.passes.size());
  for (const auto& p : run.passes) {
    const auto& m = run.manoeuvres.at(static_cast<std::size_t>(p.manoeuvre));
    const std::int64_t command_ns = m.command_delay.count();
    const std::int64_t send_ns = std::min(command_ns, send_rng.uniform_int(kSendMinNs, kSendMaxNs - 1));
    // The return sweep's first command met the link as it was then (its own stall wait).
    const std::int64_t network_ns =
        p.sweep == 0 ? m.network_delay.count()
                     : m.network_delay.count() - m.stall_wait.count() + m.return_stall_wait.count();
    const std::int64_t cause = p.cause_time.ns();
    const std::int64_t effect = p.effect_time.ns();
    StageChainTruth t;
    t.pass = p.index;
    t.true_ns = {cause + command_ns - send_ns, cause + command_ns, cause + command_ns + network_ns,
                 cause + command_ns + network_ns + m.execution_delay.count()};
    for (auto& ns : t.true_ns) ns = std::min(ns, effect);
    out.chains.push_back(t);
  }
  // Stamps from the clock model: a fresh ClockPair of the run's configuration and seed evolves as
  // the generator's did; it only moves forward, so it is queried in true-time order.
  struct Query {
    std::int64_t true_ns;
    std::size_t chain, point;
  };
  std::vector<Query> queries;
  queries.reserve(out.chains.size() * kStageMarkerCount);
  for (std::size_t c = 0; c < out.chains.size(); ++c)
    for (std::size_t k = 0; k < kStageMarkerCount; ++k) queries.push_back({out.chains[c].true_ns[k], c, k});
  std::ranges::stable_sort(queries, {}, &Query::true_ns);
  ClockPair clocks(config.cause_clock, config.effect_clock, config.sync, config.start.ns(), config.seed);
  out.marks.reserve(queries.size());
  for (const auto& q : queries) {
    auto& chain = out.chains[q.chain];
    const auto error = clocks.error(kStageMarkerBoards[q.point], q.true_ns).count();
    chain.clock_error_ns[q.point] = error;
    if (drop_rng.bernoulli(options.drop_probability)) {
      ++out.dropped;
      continue;
    }
    out.marks.push_back({chain.pass, q.point, true_time(q.true_ns),
                         core::TimePoint::from_ns(core::Clock::realtime, q.true_ns + error)});
  }
  return out;
}

std::string stage_rule_text(std::string_view cause_node, std::string_view effect_node) {
  return fmt::format(
      "operator_software = first {0}:command after cause\n"
      "send              = same key {0}:send\n"
      "network           = same key {1}:receive\n"
      "vehicle_software  = same key {1}:apply\n"
      "actuator          = effect\n",
      cause_node, effect_node);
}

}  // namespace m2mlat::sim
