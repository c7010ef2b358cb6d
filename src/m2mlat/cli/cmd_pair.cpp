// `m2mlat pair`: pair cause and effect edges and write the pairs (and the unmatched events).
#include <fmt/format.h>

#include <fstream>
#include <memory>

#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"

namespace m2mlat::cli {

namespace {
struct PairCommand {
  InputFlags inputs;
  SelectionFlags selection;
  MatchFlags match;
  std::string out;
  std::string out_format = "pairs-csv";
  std::string unmatched_out;
  bool json = false;
};

// Unmatched events as CSV: side, index in the side's input, source id (store seq or file index), time,
// reason.
void write_unmatched(const std::string& path, const std::vector<analysis::ScenarioResult>& results) {
  core::write_output_file(path, [&](std::ostream& out) {
    out << "scenario,side,node,channel,source_id,time_ns,reason\n";
    for (const auto& r : results)
      for (const auto& u : r.match.unmatched) {
        const bool cause = u.side == pairing::Side::cause;
        const auto& ref = cause ? r.input.cause_ref : r.input.effect_ref;
        out << r.input.scenario << ',' << pairing::to_string(u.side) << ',' << ref.node << ',' << ref.channel
            << ',' << r.seq(u) << ',' << u.time.ns() << ',' << pairing::to_string(u.reason) << '\n';
      }
  });
}
}  // namespace

Runner attach_pair(CLI::App& sub) {
  auto c = std::make_shared<PairCommand>();
  c->inputs.add_to(sub, false);
  c->selection.add_to(sub);
  c->match.add_to(sub);
  sub.add_option("-o,--out", c->out, "Write the pairs to this file ('-' = stdout)");
  sub.add_option("--out-format", c->out_format, "pairs-csv, pairs-jsonl or rig-paired-csv")
      ->capture_default_str();
  sub.add_option("--unmatched", c->unmatched_out, "Write the unmatched events with their reasons (CSV)");
  sub.add_flag("--json", c->json, "Print the pairing counts as JSON");
  return [c] {
    auto inputs = c->inputs;
    inputs.rematch = true;  // pairing is what this command is for
    StatsFlags no_bootstrap;
    no_bootstrap.bootstrap = 0;
    const auto pipeline = pipeline_options(c->selection, c->match, no_bootstrap);
    const auto results = analysis::analyse_inputs(inputs.pipeline_inputs(), pipeline);
    if (!c->out.empty()) {
      const auto format = formats::parse_format(c->out_format);
      std::vector<pairing::Pair> all;
      analysis::UncertaintyColumns columns;
      bool any_clock = false;
      for (const auto& r : results) {
        all.insert(all.end(), r.match.pairs.begin(), r.match.pairs.end());
        analysis::append_columns(columns, r.uncertainty, r.match.pairs.size());
        any_clock |= !r.uncertainty.empty();
      }
      formats::PairExportOptions options;
      if (any_clock)
        options.uncertainty_ns = columns.max_error_ns, options.est_error_ns = columns.est_error_ns;
      if (!results.empty())
        options.cause = results.front().input.cause_ref, options.effect = results.front().input.effect_ref;
      if (results.size() > 1) warn("several scenarios are written to one pairs file, one after another");
      formats::export_pairs(c->out, format, all, options);
    }
    if (!c->unmatched_out.empty()) write_unmatched(c->unmatched_out, results);
    if (c->json) {
      nlohmann::json doc{{"format", report::kStatsFormat}, {"scenarios", nlohmann::json::array()}};
      for (const auto& r : results)
        doc["scenarios"].push_back({{"scenario", r.input.scenario}, {"pairing", report::pairing_json(r)}});
      print_json(doc);
    } else if (c->out != "-") {
      fmt::print("{}", report::pairing_table(results));
    }
    return 0;
  };
}

}  // namespace m2mlat::cli
