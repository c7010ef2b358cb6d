// `m2mlat demo`: a complete simulated campaign with no hardware. Four scenarios like the reference
// field study's are simulated, recorded through the real store, read back, paired by the matcher and
// summarised; the pairs are then checked against the simulator's ground truth. The full-loop
// scenarios (full_loop, full_loop_baseline, full_loop_single_board; sim/full_loop.hpp) simulate the
// gyroscopes, the LED and the camera-to-screen path instead, find the onsets in the raw traces, build
// the chains (analysis/chains.hpp) and check M2M, G2G and E2E against the truth.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>

#include "m2mlat/analysis/chain_truth.hpp"
#include "m2mlat/analysis/chains.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/truth_check.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/cli/report_files.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/nearest.hpp"
#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/report/chain_truth_text.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/report_model.hpp"
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/table.hpp"
#include "m2mlat/sim/full_loop.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/presets.hpp"

namespace m2mlat::cli {

namespace {

struct DemoCommand {
  std::string store_path;  // empty: a temporary store, removed afterwards
  std::string report_dir;  // the campaign's report (report.html, ...) written here; empty: none
  std::vector<std::string> scenarios{"static_wifi", "static_5g", "dynamic_co_referenced",
                                     "dynamic_autonomous"};
  std::uint64_t seed = 1;
  std::int64_t manoeuvres = 0;         // 0: the presets' own count
  std::vector<std::string> overrides;  // simulator settings, key=value, applied to every scenario
  std::string detector = "flank";      // the full-loop scenarios' onset detector
  std::string baseline;                // the comparisons' baseline (default: the first scenario)
  MatchFlags match;
  StatsFlags stats;
  bool json = false;
};

// The full-loop scenarios: simulated, their onsets found in the raw traces, chained and checked.
struct FullLoopDemo {
  std::vector<analysis::FullLoopResult> results;
  std::vector<report::NamedChainCheck> checks;
};

FullLoopDemo run_full_loops(const DemoCommand& c,
                            const std::vector<std::pair<std::size_t, sim::FullLoopConfig>>& configs) {
  FullLoopDemo demo;
  analysis::ChainOptions options;
  options.detector = c.detector;
  options.uncertainty = c.stats.uncertainty_options();
  // The twin's boards know their whole offset error (their clock samples' est_error): no path
  // asymmetry is left for path_u to stand for.
  options.uncertainty.path_u = core::Duration{0};
  for (const auto& [k, config] : configs) {
    const auto name = c.scenarios[k];
    progress(fmt::format("simulating {}", name));
    const auto run = sim::simulate_full_loop(config);
    progress(fmt::format("chaining {}", name));
    auto chains = analysis::build_chains(analysis::chain_input(run), options, c.stats.options(), name);
    demo.checks.push_back({name, analysis::check_chains(chains, run)});
    demo.results.push_back(std::move(chains.loop));
  }
  progress_done();
  return demo;
}

int run_demo(const DemoCommand& c) {
  if (!c.baseline.empty() && std::find(c.scenarios.begin(), c.scenarios.end(), c.baseline) == c.scenarios.end())
    throw core::Error(core::ErrorKind::usage, fmt::format("--baseline: no scenario '{}'{}", c.baseline,
                                                          core::did_you_mean(c.baseline, c.scenarios)));
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
  std::vector<std::pair<std::size_t, sim::FullLoopConfig>> loops;
  for (std::size_t k = 0; k < c.scenarios.size(); ++k) {
    if (auto loop = sim::full_loop_preset(c.scenarios[k])) {
      if (!c.overrides.empty())
        throw core::Error(core::ErrorKind::usage,
                          fmt::format("--set applies to the Hall scenarios, not to {}", c.scenarios[k]));
      loop->seed = c.seed + k;
      if (c.manoeuvres > 0)
        loop->manoeuvres = static_cast<int>(std::min<std::int64_t>(c.manoeuvres, 100'000));
      sim::check(*loop);
      loops.emplace_back(k, *loop);
      continue;
    }
    auto config = sim::preset(c.scenarios[k]);
    config.seed = c.seed + k;  // each scenario its own random stream
    // The wheels' lines recorded with both edges, as docs/matcher.md advises against interference:
    // each pass a pulse, interference a pulse of microseconds that the automatic --min-pulse drops.
    config.cause_sensor.both_edges = config.effect_sensor.both_edges = true;
    if (c.manoeuvres > 0) config.manoeuvres = c.manoeuvres;
    if (!c.match.magnets.empty()) config.magnets_deg = c.match.magnets;  // the wheels and the matcher
    sim::apply_overrides(config, c.overrides);  // validates the whole configuration
    configs.push_back(std::move(config));
  }

  static_cast<void>(onset::detector(c.detector));  // an unknown name stops the demo here
  const auto full_loop = run_full_loops(c, loops);
  std::vector<analysis::ScenarioResult> results;
  std::vector<analysis::TruthCheck> checks;
  if (!configs.empty()) {
    auto store = store::Store::open(path);
    for (const sim::RigConfig& config : configs) {
      std::vector<sim::TruePair> truth;
      // Each node's events' timestamps (INT64_MIN: a rising edge), to find the true pairs' edges in
      // the columns the matcher sees (analysis::in_columns).
      std::vector<std::int64_t> cause_stamps, effect_stamps;
      const auto keep_stamps = [](const std::vector<core::Event>& events, std::vector<std::int64_t>& stamps) {
        for (const auto& e : events)
          stamps.push_back(e.edge == core::Edge::falling ? e.time.ns()
                                                         : std::numeric_limits<std::int64_t>::min());
      };
      capture::record_simulation(store, config, "demo", [&](const sim::Chunk& chunk, std::int64_t events) {
        truth.insert(truth.end(), chunk.pairs.begin(), chunk.pairs.end());
        keep_stamps(chunk.cause_events, cause_stamps);
        keep_stamps(chunk.effect_events, effect_stamps);
        progress(fmt::format("simulating {}: {} events", config.scenario, events));
      });
      progress(fmt::format("pairing {}", config.scenario));
      // Read back from the store: the same path, and the same interference filter (automatic: the
      // lines hold both edges), as `m2mlat stats` of the store takes.
      auto input = analysis::load_scenario(store, config.scenario, analysis::Selection{});
      truth = analysis::in_columns(std::move(truth), cause_stamps, effect_stamps, input);
      results.push_back(
          analysis::analyse(std::move(input), match_options, summary_options, c.match.include_ambiguous));
      // The per-sample uncertainty from the recorded clock samples, to be checked against the truth.
      analysis::attach_board_record(results.back(), store, uncertainty_options, summary_options);
      checks.push_back(analysis::check_against_truth(results.back(), truth));
    }
    progress_done();
  }
  if (temporary && !configs.empty()) {
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix, ignored);
  }

  if (c.json) {
    auto doc = report::stats_document(results, checks);
    if (!temporary && !configs.empty()) doc["store"] = path;
    if (!loops.empty()) {
      doc["full_loop"] = report::full_loop_json(full_loop.results);
      doc["full_loop_truth"] = report::chain_truth_json(full_loop.checks);
    }
    print_json(doc);
  } else {
    fmt::print("Simulated campaign: {} scenarios, seed {}{}\n\n", results.size() + loops.size(), c.seed,
               temporary || configs.empty() ? "" : fmt::format(", store {}", path));
    if (!loops.empty())
      fmt::print("{}\n{}{}", report::full_loop_table(full_loop.results),
                 report::chain_truth_table(full_loop.checks), configs.empty() ? "" : "\n");
  }
  if (!c.json && !configs.empty()) {
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
  if (!c.report_dir.empty()) {  // the same report `m2mlat report` gives of a store
    auto r = new_report();
    for (auto& result : results) r.scenarios.push_back(report::scenario_report(std::move(result)));
    r.full_loops = full_loop.results;
    report::assign_groups(r, {}, true);
    add_comparisons(r, {}, false, c.stats, c.baseline);
    progress_done();
    write_report_folder(r, c.report_dir);
    if (!c.json) fmt::print("\nreport: {}/report.html (and report.md, report.json, CSV, pgfplots/)\n", c.report_dir);
  }
  // The demo is also a self-check: it fails when a wrong pair reaches the statistics with no flag
  // telling why, or when the matcher finds too few of the true pairs.
  for (const auto& t : checks)
    if (!t.passes()) return 1;
  for (const auto& t : full_loop.checks)
    if (!t.check.passes()) return 1;
  return 0;
}

}  // namespace

Runner attach_demo(CLI::App& sub) {
  auto c = std::make_shared<DemoCommand>();
  sub.add_option("--store", c->store_path, "Keep the campaign in this new store file (default: temporary)");
  sub.add_option("--report", c->report_dir,
                 "Write the campaign's report here: report.html, report.md, report.json, CSV and pgfplots/ "
                 "(as `m2mlat report --out`)");
  sub.add_option("--scenario", c->scenarios,
                 "Scenarios to simulate (presets, or full_loop, full_loop_baseline, full_loop_single_board: "
                 "gyroscopes, LED and camera to screen; repeatable)")
      ->capture_default_str();
  sub.add_option("--seed", c->seed, "Seed of the first scenario (the next ones use seed+1, ...)")
      ->capture_default_str();
  sub.add_option("--manoeuvres", c->manoeuvres, "Manoeuvres per scenario (default: the preset's)");
  sub.add_option("--set", c->overrides,
                 "Override a simulator setting in every scenario, key=value (repeatable; `m2mlat simulate "
                 "--list` shows the keys)");
  sub.add_option("--baseline", c->baseline,
                 "The comparisons' baseline: every other scenario of its group against it (default: the "
                 "first scenario given)");
  sub.add_option("--detector", c->detector, "Onset detector of the full-loop scenarios (flank, reference)")
      ->capture_default_str();
  c->match.add_to(sub);
  c->stats.add_to(sub);
  sub.add_flag("--json", c->json, "Print m2mlat-stats/1 JSON with a truth section per scenario");
  return [c] { return run_demo(*c); };
}

}  // namespace m2mlat::cli
