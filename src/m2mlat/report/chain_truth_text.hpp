// The full-loop chains' check against the simulator's truth shown (`m2mlat demo --scenario
// full_loop`): per scenario and quantity (M2M, G2G, E2E, and each side's onset) the error against the
// truth, median and p5..p95 in ms, and the share within the stated U95; and as JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "m2mlat/analysis/chain_truth.hpp"

namespace m2mlat::report {

struct NamedChainCheck {
  std::string scenario;
  analysis::ChainTruthCheck check;
};

std::string chain_truth_table(std::span<const NamedChainCheck> checks);
nlohmann::json chain_truth_json(std::span<const NamedChainCheck> checks);

}  // namespace m2mlat::report
