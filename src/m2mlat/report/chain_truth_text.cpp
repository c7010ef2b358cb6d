// The chains' truth check as a table and as JSON (see chain_truth_text.hpp).
#include "m2mlat/report/chain_truth_text.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "m2mlat/formats/json_number.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

using formats::number;

namespace {

std::string ms(double ns) { return std::isnan(ns) ? "-" : fmt::format("{:+.3f}", ns / 1e6); }

// The rows of one check: the three quantities, then the onsets.
std::array<std::pair<const char*, const analysis::ErrorStats*>, 5> rows(const analysis::ChainTruthCheck& c) {
  return {{{"M2M", &c.errors[0]},
           {"G2G", &c.errors[1]},
           {"E2E", &c.errors[2]},
           {"station onset", &c.station_onset},
           {"vehicle onset", &c.vehicle_onset}}};
}

}  // namespace

std::string chain_truth_table(std::span<const NamedChainCheck> checks) {
  Table table(
      {"scenario", "quantity", "n", "median error", "p5..p95 error", "within U95", "chains", "check"});
  for (const auto& [scenario, c] : checks)
    for (const auto& [name, e] : rows(c)) {
      if (e->n == 0) continue;
      table.add_row({scenario, name, std::to_string(e->n), ms(e->median_ns),
                     fmt::format("{}..{}", ms(e->p5_ns), ms(e->p95_ns)),
                     e->with_u == 0 ? "-"
                                    : fmt::format("{:.1f} %", 100.0 * static_cast<double>(e->within_u95) /
                                                                  static_cast<double>(e->with_u)),
                     fmt::format("{}/{}", c.complete, c.manoeuvres), c.passes() ? "pass" : "FAIL"});
    }
  return fmt::format(
      "against the simulator's truth (error = measured - true, ms; onset: detected - true; chains: complete "
      "chains / manoeuvres; check: at least {:g} % complete, none twice, |median E2E error| <= {:g} ms over "
      "{} chains or more)\n{}",
      analysis::kMinCompletePercent, static_cast<double>(analysis::kMaxMedianErrorNs) / 1e6,
      analysis::kMinChainsForBias, table.render());
}

nlohmann::json chain_truth_json(std::span<const NamedChainCheck> checks) {
  auto out = nlohmann::json::array();
  for (const auto& [scenario, c] : checks) {
    nlohmann::json errors = nlohmann::json::object();
    for (const auto& [name, e] : rows(c))
      errors[name] = {{"n", e->n},
                      {"median_ns", number(e->median_ns)},
                      {"p5_ns", number(e->p5_ns)},
                      {"p95_ns", number(e->p95_ns)},
                      {"within_u95", e->within_u95},
                      {"with_u", e->with_u}};
    out.push_back({{"scenario", scenario},
                   {"manoeuvres", c.manoeuvres},
                   {"complete", c.complete},
                   {"duplicate", c.duplicate},
                   {"passes", c.passes()},
                   {"errors", errors}});
  }
  return out;
}

}  // namespace m2mlat::report
