// `m2mlat import`: read data files (the reference rig's formats or m2mlat's own) into a store.
// Every file is read and checked whole before anything is written, so malformed input stores
// nothing; each node of each file becomes one closed session.
#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct ImportCommand {
  std::vector<std::string> files;
  std::string store_path;
  std::string format;
  std::string node = "local";
  std::string channel;
  std::string line;
  std::string role;
  std::string scenario;
  std::string label = "import";
  bool json = false;
};

// One session to be written: a node's events from one file.
struct PendingSession {
  store::Session session;
  std::vector<core::Event> events;
};

core::Role role_for(const ImportCommand& c, const std::string& node) {
  if (!c.role.empty()) return core::parse_role(c.role);
  try {
    return core::parse_role(node);  // "operator", "vehicle", "cause", "effect" name their role
  } catch (const core::Error&) {
    return core::Role::observer;
  }
}

// Groups a file's events by node, in file order of first appearance.
std::vector<PendingSession> sessions_of(const ImportCommand& c, const std::string& path,
                                        formats::Format format, std::vector<core::Event> events) {
  std::vector<PendingSession> out;
  std::map<std::string, std::size_t> index;
  for (auto& e : events) {
    auto [it, added] = index.try_emplace(e.node, out.size());
    if (added) {
      PendingSession p;
      p.session.node = e.node;
      p.session.role = role_for(c, e.node);
      p.session.label = c.label;
      p.session.scenario = c.scenario.empty() ? std::filesystem::path(path).stem().string() : c.scenario;
      p.session.config_json =
          nlohmann::json{{"source", "import"}, {"file", path}, {"format", formats::to_string(format)}}.dump(
              -1, ' ', false, nlohmann::json::error_handler_t::replace);  // a file name need not be UTF-8
      out.push_back(std::move(p));
    }
    out[it->second].events.push_back(std::move(e));
  }
  for (auto& p : out) {
    const auto [first, last] =
        std::minmax_element(p.events.begin(), p.events.end(),
                            [](const auto& a, const auto& b) { return a.time.ns() < b.time.ns(); });
    p.session.start = first->time;
    p.session.end = last->time;
  }
  return out;
}

int run_import(const ImportCommand& c) {
  formats::ImportOptions options;
  options.node = c.node;
  options.channel = c.channel;
  options.only_line = c.line;
  const std::optional<formats::Format> format =
      c.format.empty() ? std::nullopt : std::optional(formats::parse_format(c.format));

  // Read and check everything first, before the store is opened: the files are read raw, and a
  // process must not open and close a file it holds SQLite connections to (docs/store.md).
  std::vector<PendingSession> pending;
  nlohmann::json report = nlohmann::json::array();
  for (const auto& path : c.files) {
    auto file = formats::import_file(path, format, options);
    nlohmann::json entry{{"file", path}, {"format", formats::to_string(file.format)}};
    std::vector<core::Event> events;
    if (auto* e = std::get_if<formats::EventImport>(&file.content)) {
      entry["records"] = e->records;
      entry["ignored_lines"] = e->ignored_lines;
      entry["skipped_lines"] = e->skipped_lines;
      events = std::move(e->events);
    } else if (auto* p = std::get_if<formats::PairedImport>(&file.content)) {
      entry["records"] = p->pairs.size();
      entry["latency_disagreements"] = p->disagreements.size();
      for (auto k : p->disagreements)
        warn(fmt::format("{}:{}: m2m_latency_ms differs from vehicle - remote_station by {} ns", path,
                         p->checks[k].line, p->checks[k].difference.count()));
      events = std::move(p->causes);
      events.insert(events.end(), std::make_move_iterator(p->effects.begin()),
                    std::make_move_iterator(p->effects.end()));
    } else {
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: a synchronisation-test file holds clock offsets, not edge events: "
                                    "summarise it with `m2mlat stats {}`",
                                    path, path));
    }
    if (events.empty()) throw core::Error(core::ErrorKind::data, fmt::format("{}: no events", path));
    auto sessions = sessions_of(c, path, file.format, std::move(events));
    entry["sessions"] = nlohmann::json::array();
    for (const auto& s : sessions)
      entry["sessions"].push_back({{"node", s.session.node},
                                   {"role", core::to_string(s.session.role)},
                                   {"scenario", s.session.scenario},
                                   {"events", s.events.size()}});
    report.push_back(entry);
    std::move(sessions.begin(), sessions.end(), std::back_inserter(pending));
  }

  // Then write: one transaction per session.
  auto store = store::Store::open(c.store_path);
  for (auto& p : pending) {
    const auto end = *p.session.end;
    p.session.end.reset();
    const auto id = store.begin_session(p.session);
    store.append_events(id, p.events);
    store.end_session(id, end);
  }
  if (c.json) {
    print_json({{"store", c.store_path}, {"files", report}});
  } else {
    for (const auto& f : report)
      for (const auto& s : f["sessions"])
        fmt::print("{} ({}): {} events of {} ({}) -> scenario '{}'\n",
                   core::printable(f["file"].get<std::string>()), f["format"].get<std::string>(),
                   s["events"].get<std::size_t>(), core::printable(s["node"].get<std::string>()),
                   s["role"].get<std::string>(), core::printable(s["scenario"].get<std::string>()));
  }
  return 0;
}

}  // namespace

Runner attach_import(CLI::App& sub) {
  auto c = std::make_shared<ImportCommand>();
  sub.add_option("files", c->files, "Files to import ('-' = standard input)")->required();
  sub.add_option("--store", c->store_path, "Store to import into (created if missing)")->required();
  sub.add_option("--format", c->format,
                 "Input format (default: detected): kernel-log, rig-export-csv, "
                 "rig-paired-csv, events-csv, events-jsonl");
  sub.add_option("--node", c->node, "Node of formats that name none (kernel log, export CSV)")
      ->capture_default_str();
  sub.add_option("--channel", c->channel, "Channel of those events (default gpio<pin>)");
  sub.add_option("--line", c->line, "Only this GPIO pin / Line label of a kernel log or export CSV");
  sub.add_option("--role", c->role,
                 "Role of the imported node: cause/operator, effect/vehicle, observer "
                 "(default: from the node's name)");
  sub.add_option("--scenario", c->scenario, "Scenario of the sessions (default: the file's name)");
  sub.add_option("--label", c->label, "Label of the sessions")->capture_default_str();
  sub.add_flag("--json", c->json, "Print what was imported as JSON");
  return [c] { return run_import(*c); };
}

}  // namespace m2mlat::cli
