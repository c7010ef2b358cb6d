#include "m2mlat/cli/breakdown_flags.hpp"

#include "m2mlat/analysis/scenario_breakdown.hpp"
#include "m2mlat/analysis/stage_rule.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/markers/markers_reader.hpp"
#include "m2mlat/markers/stored_markers.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

void BreakdownFlags::add_to(CLI::App& sub) {
  auto* group = sub.add_option_group("breakdown");
  group->add_option("--markers", marker_files,
                    "Markers (m2mlat-markers/1 CSV: `packets --csv`, `simulate --markers`) for the stage "
                    "breakdown (repeatable)");
  group->add_option("--stages", stages_file,
                    "Stage rule: one 'NAME = SELECTOR' a line, the last ending at 'effect' (docs/breakdown.md)");
  group->add_option("--breakdown-csv", csv_file, "Write each event's stages here (m2mlat-breakdown/1)");
}

void BreakdownFlags::apply(std::vector<analysis::ScenarioResult>& results,
                           std::span<const std::string> inputs) const {
  if (stages_file.empty()) {
    if (!marker_files.empty() || !csv_file.empty())
      throw core::Error(core::ErrorKind::usage,
                        "--markers and --breakdown-csv need --stages FILE: the rule that cuts each event into stages");
    return;
  }
  // Everything is read before anything is computed: a bad file leaves no partial breakdown.
  const auto rule = analysis::read_stage_rule(stages_file);
  std::vector<markers::Marker> all;
  const auto add = [&all](std::vector<markers::Marker> some) {
    all.insert(all.end(), std::make_move_iterator(some.begin()), std::make_move_iterator(some.end()));
  };
  for (const auto& file : marker_files) add(markers::read_markers_file(file));
  for (const auto& path : inputs)
    if (is_sqlite_file(path)) {
      store::Options options;
      options.read_only = true;
      add(markers::store_markers(store::Store::open(path, options)));
    }
  if (all.empty())
    throw core::Error(core::ErrorKind::usage,
                      "--stages needs markers: give --markers FILE (repeatable), or a store that holds some "
                      "(an agent's --mark-port, m2mlat bag --store)");
  const analysis::MarkerIndex index(all);
  for (auto& r : results) analysis::attach_breakdown(r, rule, index);
}

void BreakdownFlags::write_csv(std::span<const analysis::ScenarioResult> results) const {
  if (csv_file.empty()) return;
  core::write_output_file(csv_file, report::breakdown_csv(report::with_breakdown(results)));
}

}  // namespace m2mlat::cli
