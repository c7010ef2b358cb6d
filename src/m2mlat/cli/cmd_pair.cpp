// `m2mlat pair`: pair cause and effect edges and write the pairs (and the unmatched events).
#include <fmt/format.h>

#include <memory>

#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/pairs_file.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/store/store.hpp"

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
      // One store: every row also names its cause event's session and label.
      const auto& paths = inputs.inputs;
      const bool one_store = paths.size() == 1 && inputs.cause_file.empty() && store::is_sqlite_database(paths[0]);
      analysis::write_pairs_file(c->out, format, results,
                                 one_store ? analysis::store_pair_sessions(paths[0], results)
                                           : analysis::PairSessions{});
    }
    if (!c->unmatched_out.empty()) analysis::write_unmatched_file(c->unmatched_out, results);
    if (c->json) {
      print_json(report::pairing_document(results));
    } else if (c->out != "-") {
      fmt::print("{}", report::pairing_table(results));
      if (const auto s = report::clock_step_table(results); !s.empty()) fmt::print("\n{}", s);
    }
    return 0;
  };
}

}  // namespace m2mlat::cli
