// `m2mlat report`: statistics, comparisons and figures of one or more scenarios, from campaign stores
// or data files, as a terminal table, Markdown, CSV, JSON (m2mlat-report/1), a self-contained HTML
// page and pgfplots figures. Everything is recomputed from the raw events on every run, so other
// matcher windows, thresholds or groupings are a matter of re-running the command (docs/report.md).
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <sstream>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/archive_inputs.hpp"
#include "m2mlat/cli/breakdown_flags.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/cli/report_files.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/html_report.hpp"
#include "m2mlat/report/pgfplots.hpp"
#include "m2mlat/report/report_json.hpp"
#include "m2mlat/report/report_tables.hpp"

namespace m2mlat::cli {

namespace {

struct ReportCommand {
  InputFlags inputs;
  ArchiveFlags archive;
  SelectionFlags selection;
  MatchFlags match;
  StatsFlags stats;
  ChainFlags chains;
  BreakdownFlags breakdown;
  std::vector<std::string> groups;  // NAME=s1,s2
  bool no_groups = false;
  std::vector<std::string> compares;  // SUBJECT:BASELINE
  bool no_compare = false;
  std::string baseline;  // the default comparisons' baseline (default: the first scenario given)
  std::string uncertainty;  // duration; empty = unknown where no clock data
  double alpha = 0.05;
  std::string format = "text";
  std::string out_dir, html, pgfplots_dir;
};

std::vector<std::pair<std::string, std::vector<std::string>>> parse_groups(
    const std::vector<std::string>& specs) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("--group '{}': expected NAME=scenario,scenario,...", spec));
    std::vector<std::string> members;
    std::stringstream list(spec.substr(eq + 1));
    for (std::string m; std::getline(list, m, ',');)
      if (!m.empty()) members.push_back(m);
    out.emplace_back(spec.substr(0, eq), std::move(members));
  }
  return out;
}

report::Report build(const ReportCommand& c) {
  report::Report r = new_report();
  r.alpha = c.alpha;
  if (!(c.alpha > 0 && c.alpha < 1))
    throw core::Error(core::ErrorKind::usage, fmt::format("--alpha {} is not in (0, 1)", c.alpha));
  if (!c.uncertainty.empty()) {
    try {
      r.assumed_uncertainty_ms = static_cast<double>(core::parse_duration(c.uncertainty).count()) / 1e6;
    } catch (const core::Error& e) {
      throw core::Error(core::ErrorKind::usage, fmt::format("--uncertainty: {}", e.what()));
    }
  }

  // Everything shown (pairs, statistics, per-pair bounds, clock series, losses) comes back from the
  // pipeline: no store is opened here.
  const auto pipeline = pipeline_options(c.selection, c.match, c.stats);
  auto flags = c.inputs;
  bool archived = false;
  auto results = analyse_archive(flags, c.archive, pipeline, archived);
  auto inputs = flags.pipeline_inputs();
  r.full_loops = analysis::take_full_loop_files(inputs.inputs, inputs.format, pipeline.summary);
  for (auto& chains : c.chains.take(inputs, c.selection, c.stats)) r.full_loops.push_back(std::move(chains));
  if (!inputs.inputs.empty() || !inputs.cause_file.empty() || (r.full_loops.empty() && !archived))
    for (auto& res : analysis::analyse_inputs(inputs, pipeline)) results.push_back(std::move(res));
  c.breakdown.apply(results, inputs.inputs);
  c.breakdown.write_csv(results);
  for (auto& res : results) r.scenarios.push_back(report::scenario_report(std::move(res)));

  report::assign_groups(r, parse_groups(c.groups), !c.no_groups);

  add_comparisons(r, c.compares, c.no_compare, c.stats, c.baseline);
  progress_done();
  return r;
}

}  // namespace

Runner attach_report(CLI::App& sub) {
  auto c = std::make_shared<ReportCommand>();
  c->inputs.add_to(sub, true);
  c->archive.add_to(sub);
  c->selection.add_to(sub);
  c->match.add_to(sub);
  c->stats.add_to(sub);
  c->chains.add_to(sub);
  c->breakdown.add_to(sub);
  auto* g = sub.add_option_group("report");
  g->add_option(
      "--group", c->groups,
      "A group of scenarios for the plots and default comparisons: NAME=s1,s2 (repeatable; default: "
      "by the name's prefix before '_' or '-')");
  g->add_flag("--no-groups", c->no_groups, "Do not group scenarios by name");
  g->add_option("--compare", c->compares,
                "Compare two scenarios, SUBJECT:BASELINE (repeatable; default: within each group, each later "
                "scenario against each earlier one, or against --baseline)");
  g->add_flag("--no-compare", c->no_compare, "No comparisons");
  g->add_option("--baseline", c->baseline,
                "The default comparisons' baseline: every other scenario of its group against it (default: "
                "the first scenario given, --scenario or the store's order)");
  g->add_option("--uncertainty", c->uncertainty,
                "Measurement uncertainty per latency (e.g. 1ms) for scenarios without clock samples");
  g->add_option("--alpha", c->alpha, "Significance level of the tests")->capture_default_str();
  g->add_option("--print", c->format,
                "What to print: text, markdown, csv (scenarios), csv-comparisons, csv-full-loop or json")
      ->check(CLI::IsMember({"text", "markdown", "csv", "csv-comparisons", "csv-full-loop", "json"}))
      ->capture_default_str();
  g->add_option(
      "--out", c->out_dir,
      "Write report.html, report.md, report.json, scenarios.csv, comparisons.csv, full_loop.csv (full-loop "
      "files) and pgfplots/ here");
  g->add_option("--html", c->html, "Write the HTML report to this file");
  g->add_option("--pgfplots", c->pgfplots_dir, "Write pgfplots figures and their data into this folder");
  return [c] {
    const auto r = build(*c);
    if (!c->out_dir.empty()) write_report_folder(r, c->out_dir);
    if (!c->html.empty()) core::write_output_file(c->html, report::report_html(r));
    if (!c->pgfplots_dir.empty()) report::write_pgfplots(r, c->pgfplots_dir);
    if (c->format == "json")
      print_json(report::report_document(r));
    else if (c->format == "markdown")
      fmt::print("{}", report::report_markdown(r));
    else if (c->format == "csv")
      fmt::print("{}", report::scenarios_csv(r));
    else if (c->format == "csv-comparisons")
      fmt::print("{}", report::comparisons_csv(r));
    else if (c->format == "csv-full-loop")
      fmt::print("{}", report::full_loop_csv(r.full_loops));
    else
      fmt::print("{}", report::report_text(r));
    return 0;
  };
}

}  // namespace m2mlat::cli
