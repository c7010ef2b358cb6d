// The offline pipeline every number of `pair`, `stats`, `export --what pairs` and `report` takes:
// inputs (campaign stores, data files, or a cause file and an effect file) -> one ScenarioInput per
// scenario -> the boards' clock steps (clock_steps.hpp: from the store's or the files' clock records
// and a kernel log's own stamps) -> pairing -> statistics -> per-sample uncertainty, and the boards'
// clock samples and losses (board_record.hpp). A caller gets everything it shows from the result and
// opens no store afterwards.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

// What to read.
struct PipelineInputs {
  std::vector<std::string> inputs;     // stores (SQLite files) or data files (one scenario each); "-" = stdin
  std::vector<std::string> scenarios;  // only these scenarios of the stores; empty = all
  std::string cause_file, effect_file;    // one scenario from two files (both or neither)
  std::optional<formats::Format> format;  // of the data files; unset = detected from the content
  bool rematch = false;  // re-pair a paired-results CSV instead of using its rows as the pairs
  // (store path, scenario) left out: analysed elsewhere (the full loop's chains, store_chains.hpp).
  std::vector<std::pair<std::string, std::string>> skip;
};

// How to analyse it.
struct PipelineOptions {
  Selection selection;
  pairing::MatchOptions match;
  bool include_ambiguous = false;  // statistics over ambiguous pairs too
  stats::SummaryOptions summary;
  UncertaintyOptions uncertainty;  // applied to scenarios with clock samples: stores, events files with clock records
};

// Loads and analyses every selected scenario: the cause/effect files first, then each input in the
// order given, a store's scenarios in the order of their first session. Throws core::Error naming
// the file, line or scenario (usage when no input is given or only one of cause/effect file).
std::vector<ScenarioResult> analyse_inputs(const PipelineInputs& inputs, const PipelineOptions& options);

// One scenario of an open store, the same way (`collect`'s live view re-runs it as the store grows,
// so that its numbers are the offline ones, clock steps corrected).
ScenarioResult analyse_store_scenario(const store::Store& store, const std::string& scenario,
                                      const PipelineOptions& options);

}  // namespace m2mlat::analysis
