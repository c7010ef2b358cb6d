// `m2mlat archive`: the lab's archive in PostgreSQL. `push` copies campaign stores into it
// (idempotent, resumable), `list` shows its campaigns and scenarios with counts; `stats` and
// `report` read it (archive_inputs.hpp).
#include <fmt/chrono.h>
#include <fmt/format.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/archive/connection.hpp"
#include "m2mlat/archive/push.hpp"
#include "m2mlat/archive/read.hpp"
#include "m2mlat/cli/archive_inputs.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::cli {

namespace {

struct PushCommand {
  std::vector<std::string> args;  // stores, then optionally the URL
  std::string url_file, name, rig, label;
  std::size_t batch = 20000;
};

struct ListCommand {
  ArchiveFlags flags;  // the URL (positional here), its file and the filters
  std::vector<std::string> scenarios;
  bool json = false;
};

std::string utc_text(const std::optional<std::int64_t>& ns) {
  if (!ns) return "-";
  const std::chrono::sys_time<std::chrono::seconds> t{std::chrono::seconds{*ns / 1'000'000'000}};
  return fmt::format("{:%Y-%m-%d %H:%M:%S}", t);
}

int run_push(const PushCommand& c) {
  std::vector<std::string> stores = c.args;
  std::string url;
  if (!stores.empty() && archive::is_archive_url(stores.back())) {
    url = stores.back();
    stores.pop_back();
  }
  if (stores.empty()) throw core::Error(core::ErrorKind::usage, "archive push: give a campaign store (.db)");
  if (!c.name.empty() && stores.size() > 1)
    throw core::Error(core::ErrorKind::usage, "archive push: --name names one store; give one");
  if (c.batch == 0) throw core::Error(core::ErrorKind::usage, "--batch must be at least 1");
  auto connection = archive::Connection::open(archive::resolve_conninfo(url, c.url_file));
  for (const auto& path : stores) {
    archive::PushOptions options;
    options.name = c.name;
    options.rig = c.rig;
    options.label = c.label;
    options.batch_rows = c.batch;
    options.progress = [&](const archive::PushProgress& p) {
      progress(fmt::format("push {}: {}/{} events", path, p.events_done, p.events_total));
    };
    const auto s = archive::push(path, connection, options);
    progress_done();
    fmt::print(
        "{} -> {} campaign '{}' ({}): {}{} events, {} clock samples, {} losses, {} sessions added in {} "
        "transactions; the archive holds {} events of it\n",
        core::printable(path), connection.name(), core::printable(s.name), s.store_id,
        s.resumed ? "resumed, " : "", s.events, s.clock_samples, s.losses, s.sessions, s.batches,
        s.total_events);
  }
  return 0;
}

int run_list(const ListCommand& c) {
  const auto filter = c.flags.filter(c.scenarios);
  auto connection = archive::Connection::open(archive::resolve_conninfo(c.flags.url, c.flags.url_file));
  const auto campaigns = archive::list_campaigns(connection, filter);
  const auto names = archive::scenario_names(campaigns);
  if (c.json) {
    nlohmann::json doc = {{"format", "m2mlat-archive-list/1"}, {"campaigns", nlohmann::json::array()}};
    for (const auto& info : campaigns) {
      nlohmann::json scenarios = nlohmann::json::array();
      for (const auto& s : info.scenarios)
        scenarios.push_back({{"scenario", s.name},
                             {"name", names.at({info.id, s.name})},
                             {"sessions", s.sessions},
                             {"events", s.events}});
      doc["campaigns"].push_back(
          {{"name", info.name},
           {"store_id", info.store_id},
           {"rig", info.rig},
           {"label", info.label},
           {"created_ns", info.created_ns ? nlohmann::json(*info.created_ns) : nlohmann::json()},
           {"complete", info.complete},
           {"clock_samples", info.clock_samples},
           {"losses", info.losses},
           {"scenarios", scenarios}});
    }
    print_json(doc);
    return 0;
  }
  report::Table table({"campaign", "rig", "label", "started (UTC)", "scenario", "sessions", "events",
                       "clock samples", "losses", "push"});
  for (const auto& info : campaigns)
    for (const auto& s : info.scenarios)
      table.add_row({core::printable(info.name), core::printable(info.rig), core::printable(info.label),
                     utc_text(info.created_ns), core::printable(names.at({info.id, s.name})),
                     std::to_string(s.sessions), std::to_string(s.events), std::to_string(info.clock_samples),
                     std::to_string(info.losses), info.complete ? "complete" : "partial"});
  fmt::print("archive {}: {} campaigns\n{}", connection.name(), campaigns.size(), table.render());
  return 0;
}

}  // namespace

Runner attach_archive(CLI::App& sub) {
  sub.require_subcommand(1);
  auto push = std::make_shared<PushCommand>();
  auto* p =
      sub.add_subcommand("push", "Copy campaign stores into the archive (idempotent; a killed push resumes)");
  p->add_option("stores", push->args, "Campaign stores (.db), then the archive's postgresql://... URL")
      ->required();
  p->add_option("--url-file", push->url_file,
                "A file whose first line is the connection string (none: PG* variables)");
  p->add_option("--name", push->name,
                "The campaign's short name (default: the store's file name without .db)");
  p->add_option("--rig", push->rig, "The rig that recorded the campaign");
  p->add_option("--label", push->label, "A label for the campaign, e.g. the study's name");
  p->add_option("--batch", push->batch, "Events per transaction (default 20000)");

  auto list = std::make_shared<ListCommand>();
  auto* l = sub.add_subcommand("list", "The archive's campaigns and scenarios, with counts");
  l->add_option("url", list->flags.url, "The archive's postgresql://... URL (none: --url-file or PG* variables)");
  l->add_option("--url-file", list->flags.url_file, "A file whose first line is the connection string");
  l->add_option("--rig", list->flags.rigs, "Only campaigns of this rig (repeatable)");
  l->add_option("--campaign", list->flags.campaigns, "Only this campaign: its name or store id (repeatable)");
  l->add_option("--label", list->flags.labels, "Only campaigns with this label (repeatable)");
  l->add_option("--scenario", list->scenarios, "Only this scenario, or <campaign>/<scenario> (repeatable)");
  l->add_option("--since", list->flags.since, "Only campaigns started on or after this date (YYYY-MM-DD, UTC)");
  l->add_option("--until", list->flags.until, "Only campaigns started on or before this date (YYYY-MM-DD, UTC)");
  l->add_flag("--json", list->json, "Print m2mlat-archive-list/1 JSON");
  return [p, l, push, list] {
    if (p->parsed()) return run_push(*push);
    if (l->parsed()) return run_list(*list);
    throw core::Error(core::ErrorKind::usage, "archive needs push or list (see m2mlat archive --help)");
  };
}

}  // namespace m2mlat::cli
