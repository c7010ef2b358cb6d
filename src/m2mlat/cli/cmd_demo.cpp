// `m2mlat demo`: a complete simulated campaign with no hardware. Four scenarios like the reference
// field study's are simulated, recorded through the real store, read back, paired by the matcher and
// summarised; the pairs are then checked against the simulator's ground truth.
#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <memory>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/truth_check.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/table.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/presets.hpp"

namespace m2mlat::cli {

namespace {

struct DemoCommand {
  std::string store_path;  // empty: a temporary store, removed afterwards
  std::vector<std::string> scenarios{"static_wifi", "static_5g", "dynamic_co_referenced",
                                     "dynamic_autonomous"};
  std::uint64_t seed = 1;
  std::int64_t manoeuvres = 0;         // 0: the presets' own count
  std::vector<std::string> overrides;  // simulator settings, key=value, applied to every scenario
  MatchFlags match;
  StatsFlags stats;
  bool json = false;
};

int run_demo(const DemoCommand& c) {
  const auto match_options = c.match.options();
  const auto summary_options = c.stats.options();
  const auto uncertainty_options = c.stats.uncertainty_options();
  std::string path = c.store_path;
  const bool temporary = path.empty();
  if (temporary)
    path = (std::filesystem::temp_directory_path() / fmt::format("m2mlat-demo-{}.db", ::getpid())).string();
  else if (std::filesystem::exists(path))
    throw core::Error(core::ErrorKind::usage, fmt::format("{} exists: the demo writes a new store", path));

  // Every scenario's configuration first: a bad setting stops the demo before a store exists.
  std::vector<sim::RigConfig> configs;
  for (std::size_t k = 0; k < c.scenarios.size(); ++k) {
    auto config = sim::preset(c.scenarios[k]);
    config.seed = c.seed + k;  // each scenario its own random stream
    if (c.manoeuvres > 0) config.manoeuvres = c.manoeuvres;
    if (!c.match.magnets.empty()) config.magnets_deg = c.match.magnets;  // the wheels and the matcher
    sim::apply_overrides(config, c.overrides);  // validates the whole configuration
    configs.push_back(std::move(config));
  }

  std::vector<analysis::ScenarioResult> results;
  std::vector<analysis::TruthCheck> checks;
  {
    auto store = store::Store::open(path);
    for (const sim::RigConfig& config : configs) {
      std::vector<sim::TruePair> truth;
      capture::record_simulation(store, config, "demo", [&](const sim::Chunk& chunk, std::int64_t events) {
        truth.insert(truth.end(), chunk.pairs.begin(), chunk.pairs.end());
        progress(fmt::format("simulating {}: {} events", config.scenario, events));
      });
      progress(fmt::format("pairing {}", config.scenario));
      // Read back from the store: the same path a real campaign takes.
      results.push_back(analysis::analyse(analysis::load_scenario(store, config.scenario, {}), match_options,
                                          summary_options, c.match.include_ambiguous));
      // The per-sample uncertainty from the recorded clock samples, to be checked against the truth.
      analysis::attach_board_record(results.back(), store, uncertainty_options, summary_options);
      checks.push_back(analysis::check_against_truth(results.back(), truth));
    }
    progress_done();
  }
  if (temporary) {
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix, ignored);
  }

  if (c.json) {
    auto doc = report::stats_document(results, checks);
    if (!temporary) doc["store"] = path;
    print_json(doc);
  } else {
    fmt::print("Simulated campaign: {} scenarios, seed {}{}\n\n", results.size(), c.seed,
               temporary ? "" : fmt::format(", store {}", path));
    fmt::print("{}\n{}\n", report::pairing_table(results), report::scenario_table(results));
    report::Table table({"scenario", "true pairs", "found", "correct", "wrong flagged", "wrong unflagged",
                         "missed", "found %", "check", "true median", "measured median", "max |error|"});
    for (std::size_t k = 0; k < checks.size(); ++k) {
      const auto& t = checks[k];
      table.add_row({results[k].input.scenario, std::to_string(t.true_pairs), std::to_string(t.found),
                     std::to_string(t.correct), std::to_string(t.wrong_flagged),
                     std::to_string(t.wrong_unflagged), std::to_string(t.missed),
                     fmt::format("{:.2f}", t.found_percent()), t.passes() ? "pass" : "FAIL",
                     report::ms_text(t.true_median_ms), report::ms_text(results[k].summary.median_ms),
                     fmt::format("{:.3f} ms", static_cast<double>(t.max_abs_error_ns) / 1e6)});
    }
    fmt::print(
        "against the simulator's truth (latency in ms; error = measured - true latency of a correct "
        "pair; check: no unflagged wrong pair and at least {} % of the true pairs found)\n{}",
        analysis::kMinFoundPercent, table.render());

    report::Table coverage({"scenario", "pairs", "within u", "within U95", "within max_err", "median |error|",
                            "median U95", "U95 / |error|"});
    bool any = false;
    for (std::size_t k = 0; k < checks.size(); ++k) {
      const auto& t = checks[k];
      if (t.with_uncertainty == 0) continue;
      any = true;
      coverage.add_row(
          {results[k].input.scenario, std::to_string(t.with_uncertainty),
           report::percent_text(t.coverage_u()), report::percent_text(t.coverage_U95()),
           report::percent_text(t.coverage_max()), fmt::format("{:.3f} ms", t.median_abs_error_ns / 1e6),
           fmt::format("{:.3f} ms", t.median_U95_ns / 1e6), fmt::format("{:.2f}", t.width_ratio())});
    }
    if (any)
      fmt::print(
          "\nper-sample uncertainty against the truth (correct pairs; honest: about 68 % within u, k = 1, "
          "95 % within U95, k = 2, all within max_err)\n{}",
          coverage.render());
  }
  // The demo is also a self-check: it fails when a wrong pair reaches the statistics with no flag
  // telling why, or when the matcher finds too few of the true pairs.
  for (const auto& t : checks)
    if (!t.passes()) return 1;
  return 0;
}

}  // namespace

Runner attach_demo(CLI::App& sub) {
  auto c = std::make_shared<DemoCommand>();
  sub.add_option("--store", c->store_path, "Keep the campaign in this new store file (default: temporary)");
  sub.add_option("--scenario", c->scenarios, "Scenarios to simulate (presets; repeatable)")
      ->capture_default_str();
  sub.add_option("--seed", c->seed, "Seed of the first scenario (the next ones use seed+1, ...)")
      ->capture_default_str();
  sub.add_option("--manoeuvres", c->manoeuvres, "Manoeuvres per scenario (default: the preset's)");
  sub.add_option("--set", c->overrides,
                 "Override a simulator setting in every scenario, key=value (repeatable; `m2mlat simulate "
                 "--list` shows the keys)");
  c->match.add_to(sub);
  c->stats.add_to(sub);
  sub.add_flag("--json", c->json, "Print m2mlat-stats/1 JSON with a truth section per scenario");
  return [c] { return run_demo(*c); };
}

}  // namespace m2mlat::cli
