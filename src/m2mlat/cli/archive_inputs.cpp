// Archived campaigns analysed through temporary campaign stores.
#include "m2mlat/cli/archive_inputs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <stdlib.h>

#include <filesystem>

#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/archive/connection.hpp"
#include "m2mlat/archive/read.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

// A private folder for the temporary stores, removed with everything in it.
class TempFolder {
 public:
  TempFolder() {
    auto pattern = (std::filesystem::temp_directory_path() / "m2mlat-archive-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot make a temporary folder", pattern));
    path_ = pattern;
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  ~TempFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

void ArchiveFlags::add_to(CLI::App& sub) {
  auto* g = sub.add_option_group("archive", "Reading the lab's archive (PostgreSQL; docs/archive.md)");
  g->add_option(
      "--archive", url,
      "The archive's connection string, postgresql://... (also an input of that form; none: PG* variables)");
  g->add_option("--url-file", url_file, "A file whose first line is the archive's connection string");
  g->add_option("--rig", rigs, "Only the archive's campaigns of this rig (repeatable)");
  g->add_option("--campaign", campaigns, "Only this archived campaign: its name or store id (repeatable)");
  g->add_option("--label", labels, "Only the archive's campaigns with this label (repeatable)");
  g->add_option("--since", since,
                "Only the archive's campaigns started on or after this date (YYYY-MM-DD, UTC)");
  g->add_option("--until", until,
                "Only the archive's campaigns started on or before this date (YYYY-MM-DD, UTC)");
}

archive::CampaignFilter ArchiveFlags::filter(const std::vector<std::string>& scenarios) const {
  archive::CampaignFilter f;
  f.rigs = rigs;
  f.labels = labels;
  f.campaigns = campaigns;
  f.scenarios = scenarios;
  if (!since.empty()) f.since_ns = archive::parse_date(since, "--since");
  if (!until.empty()) f.until_ns = archive::parse_date(until, "--until") + 86'400'000'000'000;  // + one day
  return f;
}

std::vector<analysis::ScenarioResult> analyse_archive(InputFlags& inputs, const ArchiveFlags& flags,
                                                      const analysis::PipelineOptions& options, bool& used) {
  std::vector<std::string> urls;
  std::erase_if(inputs.inputs, [&](const std::string& input) {
    if (!archive::is_archive_url(input)) return false;
    urls.push_back(input);
    return true;
  });
  if (!flags.url.empty()) urls.push_back(flags.url);
  const bool filtered = !flags.rigs.empty() || !flags.labels.empty() || !flags.campaigns.empty() ||
                        !flags.since.empty() || !flags.until.empty();
  used = !urls.empty() || !flags.url_file.empty() || (filtered && inputs.inputs.empty());
  if (!used) return {};
  if (urls.size() > 1) throw core::Error(core::ErrorKind::usage, "give one archive (postgresql://...)");

  const auto filter = flags.filter(inputs.scenarios);

  auto connection =
      archive::Connection::open(archive::resolve_conninfo(urls.empty() ? "" : urls.front(), flags.url_file));
  const auto campaigns = archive::list_campaigns(connection, filter);
  if (campaigns.empty())
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("archive {}: no campaign matches the filters", connection.name()));
  const auto names = archive::scenario_names(campaigns);

  TempFolder folder;
  std::vector<analysis::ScenarioResult> results;
  for (const auto& campaign : campaigns) {
    progress(fmt::format("archive: reading campaign {}", campaign.name));
    const auto path = (folder.path() / fmt::format("campaign-{}.db", campaign.id)).string();
    analysis::PipelineInputs one;
    one.inputs = {path};
    {
      store::Options write;
      write.durability = store::Durability::off;  // a scratch copy: a crash loses nothing of value
      auto copy = store::Store::open(path, write);
      archive::read_campaign(connection, campaign, names, copy);
      // The selected scenarios, in the store's order (of their first session).
      for (const auto& name : analysis::scenarios(copy))
        for (const auto& s : campaign.scenarios)
          if (names.at({campaign.id, s.name}) == name) one.scenarios.push_back(name);
    }
    for (auto& r : analysis::analyse_inputs(one, options)) results.push_back(std::move(r));
  }
  progress_done();
  return results;
}

}  // namespace m2mlat::cli
