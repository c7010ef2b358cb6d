// The chains against the simulator's truth (see chain_truth.hpp).
#include "m2mlat/analysis/chain_truth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "m2mlat/sim/full_loop.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::analysis {

namespace {

struct Errors {
  std::vector<double> ns;
  std::size_t within = 0, with_u = 0;
  void add(std::int64_t error, const std::optional<std::int64_t>& u) {
    ns.push_back(static_cast<double>(error));
    if (!u) return;
    ++with_u;
    if (std::llabs(error) <= 2 * *u) ++within;
  }
  ErrorStats stats() && {
    ErrorStats s;
    s.n = ns.size();
    s.within_u95 = within;
    s.with_u = with_u;
    if (ns.empty()) {
      s.median_ns = s.p5_ns = s.p95_ns = std::numeric_limits<double>::quiet_NaN();
      return s;
    }
    std::sort(ns.begin(), ns.end());
    const std::span<const double> sorted(ns);
    s.median_ns = stats::quantile(sorted, 0.5);
    s.p5_ns = stats::quantile(sorted, 0.05);
    s.p95_ns = stats::quantile(sorted, 0.95);
    return s;
  }
};

}  // namespace

double ChainTruthCheck::complete_percent() const {
  return manoeuvres == 0 ? 0 : 100.0 * static_cast<double>(complete) / static_cast<double>(manoeuvres);
}

bool ChainTruthCheck::passes() const {
  // E2E; G2G where there is no E2E (one board, no gyroscopes).
  const auto& checked = errors[2].n > 0 ? errors[2] : errors[1];
  const bool unbiased =
      checked.n < kMinChainsForBias || std::fabs(checked.median_ns) <= static_cast<double>(kMaxMedianErrorNs);
  return complete_percent() >= kMinCompletePercent && duplicate == 0 && checked.n > 0 && unbiased;
}

ChainTruthCheck check_chains(const ChainResult& result, const sim::FullLoopRun& run) {
  ChainTruthCheck check;
  check.manoeuvres = run.manoeuvres.size();
  std::vector<bool> taken(run.manoeuvres.size(), false);
  std::array<Errors, 3> errors;
  Errors station, vehicle;
  for (const auto& c : result.chains) {
    if (c.gap || !c.led_ns) continue;
    // The manoeuvre whose LED was lit nearest this chain's LED stamp (on the true time base).
    const std::int64_t led_true = *c.led_ns - run.vehicle_offset_ns;
    std::size_t best = 0;
    for (std::size_t k = 1; k < run.manoeuvres.size(); ++k)
      if (std::llabs(run.manoeuvres[k].led_true_ns - led_true) <
          std::llabs(run.manoeuvres[best].led_true_ns - led_true))
        best = k;
    if (taken[best]) {
      ++check.duplicate;
      continue;
    }
    taken[best] = true;
    ++check.complete;
    const auto& m = run.manoeuvres[best];
    const auto& v = c.values;
    if (v[0].ns) errors[0].add(*v[0].ns - m.true_m2m_ns(), c.u_ns[0]);
    if (v[1].ns) errors[1].add(*v[1].ns - m.true_g2g_ns(), c.u_ns[1]);
    if (v[2].ns) errors[2].add(*v[2].ns - m.true_e2e_ns(), c.u_ns[2]);
    if (c.station_onset_ns)
      station.add(*c.station_onset_ns - run.station_offset_ns - m.station.onset_ns, std::nullopt);
    if (c.vehicle_onset_ns)
      vehicle.add(*c.vehicle_onset_ns - run.vehicle_offset_ns - m.vehicle.onset_ns, std::nullopt);
  }
  for (std::size_t q = 0; q < 3; ++q) check.errors[q] = std::move(errors[q]).stats();
  check.station_onset = std::move(station).stats();
  check.vehicle_onset = std::move(vehicle).stats();
  return check;
}

}  // namespace m2mlat::analysis
