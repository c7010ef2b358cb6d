// Coverage of the statistics' bootstrap on the simulator: the 95 % CI of the median and of the IQR of
// a run's true pairs against the population's (a run of 20,000 manoeuvres), over 100 seeds of
// dynamic_co_referenced, with 1, 4 and 9 magnets a wheel; the manoeuvres' bootstrap beside the pairs'
// one. Measured (docs/statistics.md): 1 magnet 0.95 / 0.97 both ways (median / IQR); 4 magnets 0.91 /
// 0.88 against the pairs' 0.78 / 0.79; 9 magnets 0.87 / 0.84 against 0.51 / 0.49.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "m2mlat/analysis/manoeuvres.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "m2mlat/stats/bootstrap.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat {
namespace {

struct Sample {
  std::vector<std::int64_t> latency_ns;  // the true pairs' measured latencies, in time order
  std::vector<std::size_t> manoeuvres;   // where each manoeuvre (burst) begins
};

Sample run(const std::vector<double>& magnets, std::uint64_t seed, std::int64_t manoeuvres) {
  auto config = sim::preset("dynamic_co_referenced");
  config.seed = seed;
  config.magnets_deg = magnets;
  if (manoeuvres > 0) config.manoeuvres = manoeuvres;
  const auto sim = sim::simulate(config);
  Sample s;
  std::vector<std::int64_t> causes;
  for (const auto& p : sim.pairs) {
    s.latency_ns.push_back(p.measured_latency.count());
    causes.push_back(sim.cause_events[static_cast<std::size_t>(p.cause_index)].time.ns());
  }
  s.manoeuvres = analysis::manoeuvre_starts(causes, pairing::burst_gap_for(magnets));
  return s;
}

struct Coverage {
  int median = 0, iqr = 0, runs = 0;
  double median_share() const { return static_cast<double>(median) / runs; }
  double iqr_share() const { return static_cast<double>(iqr) / runs; }
};

TEST(ResamplingCoverage, ManoeuvresCoverThePopulationsMedianAndIqrFarBetterThanPairs) {
  const std::vector<std::vector<double>> layouts{
      {0}, {45, 135, 225, 315}, {0, 40, 80, 120, 160, 200, 240, 280, 320}};
  for (const auto& magnets : layouts) {
    auto population = run(magnets, 1'000'003, 20'000).latency_ns;
    std::sort(population.begin(), population.end());
    const std::span<const std::int64_t> all(population);
    const double median_ms = stats::quantile(all, 0.5) / 1e6;
    const double iqr_ms = (stats::quantile(all, 0.75) - stats::quantile(all, 0.25)) / 1e6;
    Coverage units, pairs;
    for (std::uint64_t seed = 1; seed <= 100; ++seed) {
      const Sample s = run(magnets, seed, 0);
      const stats::BootstrapOptions options{1000, seed, 0.95};
      const auto plan = stats::plan_resampling(s.latency_ns, s.manoeuvres);
      ASSERT_EQ(plan.grouped(), magnets.size() > 1);
      const auto by_units = stats::resample_median_iqr(s.latency_ns, s.manoeuvres, plan, options);
      auto sorted = s.latency_ns;
      std::sort(sorted.begin(), sorted.end());
      const auto by_pairs = stats::bootstrap_median_iqr(sorted, options);
      ASSERT_TRUE(by_units && by_pairs);
      for (auto [coverage, ci] : {std::pair{&units, &*by_units}, std::pair{&pairs, &*by_pairs}}) {
        coverage->median += ci->median_ms.contains(median_ms) ? 1 : 0;
        coverage->iqr += ci->iqr_ms.contains(iqr_ms) ? 1 : 0;
        ++coverage->runs;
      }
    }
    const std::string name = std::to_string(magnets.size()) + " magnets";
    RecordProperty(name + ", manoeuvres: median", std::to_string(units.median_share()));
    RecordProperty(name + ", manoeuvres: IQR", std::to_string(units.iqr_share()));
    RecordProperty(name + ", pairs: median", std::to_string(pairs.median_share()));
    RecordProperty(name + ", pairs: IQR", std::to_string(pairs.iqr_share()));
    if (magnets.size() == 1) {
      // One pair a manoeuvre and no correlation: the plain bootstrap, and its coverage.
      EXPECT_EQ(units.median, pairs.median);
      EXPECT_GE(units.median_share(), 0.92) << name;
      EXPECT_GE(units.iqr_share(), 0.92) << name;
    } else {
      // Short of 0.95 (docs/statistics.md: the vehicle's queue correlates neighbouring manoeuvres), but
      // far above the pairs' bootstrap, which treats a manoeuvre's pairs as independent.
      EXPECT_GE(units.median_share(), 0.85) << name;
      EXPECT_GE(units.iqr_share(), 0.82) << name;
      EXPECT_GE(units.median_share(), pairs.median_share() + 0.1) << name;
      EXPECT_GE(units.iqr_share(), pairs.iqr_share() + 0.08) << name;
    }
    EXPECT_LE(units.median_share(), 0.99) << name;
    EXPECT_LE(units.iqr_share(), 0.99) << name;
  }
}

}  // namespace
}  // namespace m2mlat
