// Reading the archive: which campaigns and scenarios it holds (filtered across campaigns by rig,
// date, label and scenario), and one campaign's rows given back as a campaign store, so that
// `stats` and `report` analyse an archived campaign through the very pipeline a store takes
// (analysis/pipeline.hpp): the archive is another place a store's rows live, not another analysis.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/archive/connection.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::archive {

// Which campaigns and scenarios to read; an empty field matches everything.
struct CampaignFilter {
  std::vector<std::string> rigs;                   // the campaign's rig is one of these
  std::vector<std::string> labels;                 // the campaign's label is one of these
  std::vector<std::string> scenarios;              // a scenario's name, or "<campaign>/<scenario>"
  std::vector<std::string> campaigns;              // the campaign's name or store id
  std::optional<std::int64_t> since_ns, until_ns;  // created_ns in [since, until), ns since 1970 (UTC)
};

struct ScenarioCount {
  std::string name;
  std::int64_t sessions = 0, events = 0;
};

struct CampaignInfo {
  std::int64_t id = 0;
  std::string store_id, name, rig, label;
  std::optional<std::int64_t> created_ns;  // earliest session start, ns since 1970
  bool complete = false;                   // its last push ran to its end
  std::int64_t clock_samples = 0, losses = 0;
  std::vector<ScenarioCount> scenarios;  // those the filter selects, by name
};

// The campaigns the filter selects (those with at least one selected scenario), oldest first.
// Throws core::Error(io) for the database; an archive without the tables holds no campaign.
std::vector<CampaignInfo> list_campaigns(Connection& connection, const CampaignFilter& filter);

// The name each (campaign id, scenario) has in an analysis of `campaigns` together: the scenario's
// own name, or "<campaign>/<scenario>" where several of them hold a scenario of that name.
std::map<std::pair<std::int64_t, std::string>, std::string> scenario_names(
    const std::vector<CampaignInfo>& campaigns);

// Copies the whole campaign (sessions, events, clock samples, losses, raw-sample blocks) into the empty store
// `into` through store::Store::ingest (origin: the campaign's store id), in batches of `batch_rows` events,
// each session's scenario renamed by `names` where it names one. The whole campaign, in seq order, so that
// the copy's event seqs are the campaign store's (a statistic's sample id points at the same event in both)
// where that store's seqs run 1, 2, 3, ... as a store's own do. Throws core::Error: io for the database, data
// for a row the store refuses (naming the archive's table and row).
void read_campaign(Connection& connection, const CampaignInfo& campaign,
                   const std::map<std::pair<std::int64_t, std::string>, std::string>& names,
                   store::Store& into, std::size_t batch_rows = 50000);

// "YYYY-MM-DD" (UTC midnight) as ns since 1970. Throws core::Error(usage) naming `flag`.
std::int64_t parse_date(const std::string& text, const std::string& flag);

}  // namespace m2mlat::archive
