// The archive as an input of `stats` and `report`: postgresql:// inputs (or --archive URL) and the
// filters across campaigns (--rig, --since, --until, --label; --scenario as for stores). Each
// selected campaign is read back into a temporary campaign store (archive::read_campaign) and
// analysed by analysis::analyse_inputs like any store, so an archived campaign's numbers are the
// store's; a scenario that several selected campaigns hold is named "<campaign>/<scenario>".
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/archive/read.hpp"
#include "m2mlat/cli/inputs.hpp"

namespace m2mlat::cli {

struct ArchiveFlags {
  std::string url;       // --archive
  std::string url_file;  // --url-file: the connection string's file
  std::vector<std::string> rigs, labels, campaigns;
  std::string since, until;  // YYYY-MM-DD, UTC
  void add_to(CLI::App& sub);
  // The campaigns these flags and `scenarios` select (--until names the last day included). Throws
  // core::Error(usage) for a date that is not YYYY-MM-DD.
  archive::CampaignFilter filter(const std::vector<std::string>& scenarios) const;
};

// Takes the archive's URLs out of inputs.inputs and, when there is one (or --archive, or a filter
// and only PG* variables), analyses the selected scenarios of the archive. `used` tells whether the
// archive was an input at all. Throws core::Error(no_input) when the filters select nothing.
std::vector<analysis::ScenarioResult> analyse_archive(InputFlags& inputs, const ArchiveFlags& flags,
                                                      const analysis::PipelineOptions& options, bool& used);

}  // namespace m2mlat::cli
