// `m2mlat stats`: latency statistics per scenario, from stores or data files.
#include <fmt/format.h>

#include <memory>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/archive_inputs.hpp"
#include "m2mlat/cli/breakdown_flags.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::cli {

namespace {

// Offsets (t_B - t_A of one shared pulse) summarised like latencies: signed, and by magnitude.
stats::Summary offset_summary(const formats::SyncImport& sync, bool magnitude,
                              stats::SummaryOptions options) {
  std::vector<std::int64_t> offsets, lines;
  for (const auto& s : sync.samples) {
    offsets.push_back(magnitude && s.offset_ns < 0 ? -s.offset_ns : s.offset_ns);
    lines.push_back(s.line);
  }
  options.thresholds.clear();
  return stats::summarize(offsets, lines, options);
}

nlohmann::json sync_json(const std::string& path, const formats::SyncImport& sync,
                         const stats::SummaryOptions& options) {
  return {{"file", path},
          {"offset", report::summary_json(offset_summary(sync, false, options))},
          {"abs_offset", report::summary_json(offset_summary(sync, true, options))}};
}

std::string sync_text(const std::string& path, const formats::SyncImport& sync,
                      const stats::SummaryOptions& options) {
  report::Table table({"offset (ms)", "n", "mean", "sd", "min", "median", "P95", "max"});
  for (bool magnitude : {false, true}) {
    const auto s = offset_summary(sync, magnitude, options);
    table.add_row({magnitude ? "|t_B - t_A|" : "t_B - t_A", std::to_string(s.n),
                   report::ms_text(s.mean_ms, 3), report::ms_text(s.sd_ms, 3),
                   s.min ? report::ms_text(s.min->ms(), 3) : "-", report::ms_text(s.median_ms, 3),
                   report::ms_text(s.p95_ms, 3), s.max ? report::ms_text(s.max->ms(), 3) : "-"});
  }
  return fmt::format("synchronisation test {}\n{}", core::printable(path), table.render());
}

struct StatsCommand {
  InputFlags inputs;
  ArchiveFlags archive;
  SelectionFlags selection;
  MatchFlags match;
  StatsFlags stats;
  ChainFlags chains;
  BreakdownFlags breakdown;
  bool json = false;
  bool detail = false;
};
}  // namespace

Runner attach_stats(CLI::App& sub) {
  auto c = std::make_shared<StatsCommand>();
  c->inputs.add_to(sub, true);
  c->archive.add_to(sub);
  c->selection.add_to(sub);
  c->match.add_to(sub);
  c->stats.add_to(sub);
  c->chains.add_to(sub);
  c->breakdown.add_to(sub);
  sub.add_flag("--json", c->json, "Print m2mlat-stats/1 JSON instead of tables");
  sub.add_flag("--detail", c->detail, "Print every statistic of each scenario");
  return [c] {
    auto inputs = c->inputs;
    const auto pipeline = pipeline_options(c->selection, c->match, c->stats);
    // The archive's campaigns first (archive_inputs.hpp), then the stores and files.
    bool archived = false;
    auto results = analyse_archive(inputs, c->archive, pipeline, archived);
    // The full-loop rig's files (M2M, G2G, E2E per event) are summarised on their own, as are
    // synchronisation-test files (offsets between two boards).
    auto loops =
        analysis::take_full_loop_files(inputs.inputs, inputs.pipeline_inputs().format, c->stats.options());
    std::vector<std::pair<std::string, formats::SyncImport>> sync_files;
    std::erase_if(inputs.inputs, [&](const std::string& path) {
      if (is_sqlite_file(path)) return false;
      auto file = formats::import_file(path, std::nullopt, {});
      if (auto* sync = std::get_if<formats::SyncImport>(&file.content)) {
        sync_files.emplace_back(path, std::move(*sync));
        return true;
      }
      return false;
    });
    // Stores with gyroscope traces: the full loop's chains, shown with the full-loop files.
    auto pipeline_inputs = inputs.pipeline_inputs();
    for (auto& chains : c->chains.take(pipeline_inputs, c->selection, c->stats))
      loops.push_back(std::move(chains));
    if (!pipeline_inputs.inputs.empty() || !pipeline_inputs.cause_file.empty() ||
        (sync_files.empty() && loops.empty() && !archived))
      for (auto& r : analysis::analyse_inputs(pipeline_inputs, pipeline)) results.push_back(std::move(r));
    c->breakdown.apply(results, pipeline_inputs.inputs);
    c->breakdown.write_csv(results);
    if (c->json) {
      auto doc = report::stats_document(results);
      for (const auto& [path, sync] : sync_files)
        doc["sync_tests"].push_back(sync_json(path, sync, c->stats.options()));
      if (!loops.empty()) doc["full_loop"] = report::full_loop_json(loops);
      print_json(doc);
      return 0;
    }
    for (const auto& [path, sync] : sync_files) fmt::print("{}\n", sync_text(path, sync, c->stats.options()));
    if (!loops.empty()) fmt::print("{}{}", report::full_loop_table(loops), results.empty() ? "" : "\n");
    if (results.empty()) return 0;
    fmt::print("{}\n{}", report::pairing_table(results), report::scenario_table(results));
    if (const auto f = report::flagged_effect_table(results); !f.empty()) fmt::print("\n{}", f);
    if (const auto u = report::uncertainty_table(results); !u.empty()) fmt::print("\n{}", u);
    if (const auto s = report::clock_step_table(results); !s.empty()) fmt::print("\n{}", s);
    if (const auto b = report::breakdown_table(report::with_breakdown(results)); !b.empty()) fmt::print("\n{}", b);
    if (c->detail)
      for (const auto& r : results) fmt::print("\n{}", report::scenario_detail(r));
    return 0;
  };
}

}  // namespace m2mlat::cli
