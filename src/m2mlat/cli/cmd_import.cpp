// `m2mlat import`: read data files (the reference rig's formats or m2mlat's own, a gyroscope's raw
// trace among them) into a store.
// Every file is read and checked whole before anything is written, so malformed input stores
// nothing; each node of each file becomes one closed session, with the clock samples and steps the
// file carries (events files' clock records, a kernel log's steps). --clock-log adds chronyd's steps
// (formats/chrony_log.hpp) to the sessions of --node.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "m2mlat/analysis/clock_records.hpp"
#include "m2mlat/analysis/clock_steps.hpp"
#include "m2mlat/analysis/import_follow.hpp"
#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/chrony_log.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/rate_trace_csv.hpp"
#include "m2mlat/store/already_stored.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/rate_block.hpp"
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
  std::string clock_log;  // chronyd's log: its steps go to the sessions of `node`
  bool json = false;
};

// One session to be written: a node's events from one file, or a gyroscope's raw trace.
struct PendingSession {
  store::Session session;
  std::vector<core::Event> events;
  std::vector<store::ClockSample> clock;  // session_id set when written
  std::optional<core::RateTrace> trace;   // an m2mlat-gyro/1 file's samples, on channel `gyro_channel`
  std::string gyro_channel;
  std::size_t report_file = 0, report_entry = 0;  // its place in the import's report
};

core::Role role_for(const ImportCommand& c, const std::string& node);  // below

// True if the file is an m2mlat-gyro/1 trace: --format gyro, or (detected) its first line names it.
// Standard input is only taken as one with --format gyro (it cannot be read twice).
bool is_gyro_file(const ImportCommand& c, const std::string& path) {
  if (c.format == "gyro") return true;
  if (!c.format.empty() || path == "-") return false;
  std::ifstream in(path);
  std::string first;
  return std::getline(in, first) && first == fmt::format("# format: {}", formats::kRateTraceFormat);
}

// An m2mlat-gyro/1 file as one closed session of --node with its trace on --channel (default
// "gyro"). The file's own comment lines (after the fixed ones, before the column header) are kept in
// the session's configuration, so `export --what gyro` writes the file back byte for byte.
PendingSession gyro_session(const ImportCommand& c, const std::string& path) {
  const auto input = formats::InputText::read_file(path);
  formats::check_input(input.text(), input.name());
  PendingSession p;
  p.trace = formats::read_rate_trace_csv(input.text(), input.name());
  if (p.trace->samples.empty())
    throw core::Error(core::ErrorKind::data, fmt::format("{}: no samples", input.name()));
  std::vector<std::string> comments;
  formats::LineReader lines(input.text());
  std::string_view line;
  while (lines.next(line) && line.starts_with("#"))
    if (!line.starts_with("# format:") && !line.starts_with("# clock:") && !line.starts_with("# counts_per_deg_s:"))
      comments.emplace_back(line.substr(line.starts_with("# ") ? 2 : 1));
  p.gyro_channel = c.channel.empty() ? "gyro" : c.channel;
  p.session.node = c.node;
  p.session.role = role_for(c, c.node);
  p.session.label = c.label;
  p.session.scenario = c.scenario.empty() ? std::filesystem::path(path).stem().string() : c.scenario;
  p.session.config_json = nlohmann::json{{"source", "import"},
                                         {"file", path},
                                         {"format", formats::kRateTraceFormat},
                                         {"comments", comments}}
                              .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  p.session.start = core::TimePoint::from_ns(p.trace->clock, p.trace->samples.front().time_ns);
  p.session.end = core::TimePoint::from_ns(p.trace->clock, p.trace->samples.back().time_ns);
  return p;
}

// The clock samples a file carries, by node: an events file's clock records, a kernel log's steps
// (kernel_log_steps.hpp, on the node of its events; a clock slewing faster than the steps' bound is
// said on stderr, not stored). A kernel log's two stamps per line go to `log`, for the steps another
// board took over (import_follow.hpp).
std::map<std::string, std::vector<store::ClockSample>> clock_of(const formats::EventImport& file,
                                                                const std::string& path,
                                                                std::optional<analysis::LogStamps>& log) {
  std::map<std::string, std::vector<store::ClockSample>> out;
  for (const auto& r : file.clock_records) out[r.node].push_back(analysis::to_clock_sample(r));
  if (file.kernel_records.empty() || file.events.empty()) return out;
  const auto& node = file.events.front().node;
  auto stamps = analysis::log_stamps(file.kernel_records);
  if (stamps.realtime_ns.empty()) return out;
  const auto clock = analysis::kernel_log_clock(stamps.realtime_ns, stamps.log_time_us);
  for (const auto& step : clock.steps) out[node].push_back(store::step_clock_sample(step));
  for (const auto& lines : analysis::unknown_clock_runs(stamps.realtime_ns, clock.left_out))
    out[node].push_back(store::unknown_clock_sample(lines));
  if (!clock.left_out.empty()) {
    const auto outliers = std::count_if(clock.left_out.begin(), clock.left_out.end(),
                                        [](const auto& l) { return l.second == analysis::LineFault::outlier; });
    warn(fmt::format("{}: {} GPIO lines are stamped on no known clock ({} outliers: their realtime stamp "
                     "disagrees with the lines on both sides; {} before the board's first synchronisation): "
                     "their events are stored and left out of pairing (docs/sync.md)",
                     path, clock.left_out.size(), outliers, clock.left_out.size() - static_cast<std::size_t>(outliers)));
  }
  for (const auto& note : analysis::log_clock_notes(clock.limits)) warn(fmt::format("{}: {}", path, note));
  log = std::move(stamps);
  return out;
}

// chronyd's steps as step records: the line's stamp is after the step (chronyd logs it at once; the
// logger stamps it on receipt, allowed 1 s) and before the stamp's next tick; the size is exact to
// the microsecond chronyd prints.
struct ChronySteps {
  std::vector<store::ClockSample> samples;
  std::size_t failed = 0;  // "Could not step system clock": no step stored
};
ChronySteps chrony_steps(const std::string& path) {
  const auto input = formats::InputText::read_file(path);
  formats::check_input(input.text(), input.name());
  const auto log = formats::import_chrony_log(input.text(), input.name());
  ChronySteps out{{}, log.failed_steps};
  for (const auto& s : log.steps) {
    store::ClockStep step;
    step.at_ns = s.time_ns + s.resolution_ns;
    step.earliest_ns = s.time_ns - 1'000'000'000;
    step.size_ns = s.size_ns;
    if (s.size_ns) step.size_max_ns = 500, step.size_est_ns = 289;  // +-0.5 us, uniform: 0.5/sqrt(3)
    step.origin = "chrony";
    out.samples.push_back(store::step_clock_sample(step));
  }
  return out;
}

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
      nlohmann::json config{{"source", "import"}, {"file", path}, {"format", formats::to_string(format)}};
      // A kernel log is read again when the other board's is imported later (import_follow.hpp).
      if (format == formats::Format::kernel_log && path != "-")
        config["path"] = std::filesystem::absolute(path).lexically_normal().string();
      p.session.config_json =
          config.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // a file name need not be UTF-8
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

// Stores what run_import read and checked (below it).
int write_import(const ImportCommand& c, std::vector<PendingSession>& pending,
                 std::map<std::size_t, analysis::LogStamps>& logs, nlohmann::json& report,
                 const nlohmann::json& clock_logs);

int run_import(const ImportCommand& c) {
  if (c.files.empty() && c.clock_log.empty())
    throw core::Error(core::ErrorKind::usage, "nothing to import: give files and/or --clock-log");
  formats::ImportOptions options;
  options.node = c.node;
  options.channel = c.channel;
  options.only_line = c.line;
  const std::optional<formats::Format> format =
      c.format.empty() || c.format == "gyro" ? std::nullopt : std::optional(formats::parse_format(c.format));

  // Read and check everything first, before the store is opened: the files are read raw, and a
  // process must not open and close a file it holds SQLite connections to (docs/store.md).
  std::vector<PendingSession> pending;
  std::map<std::size_t, analysis::LogStamps> logs;  // a kernel log's stamps, by its session in `pending`
  nlohmann::json report = nlohmann::json::array();
  nlohmann::json clock_logs = nlohmann::json::array();
  for (const auto& path : c.files) {
    if (is_gyro_file(c, path)) {
      auto p = gyro_session(c, path);
      report.push_back({{"file", path},
                        {"format", formats::kRateTraceFormat},
                        {"sessions",
                         {{{"node", p.session.node},
                           {"role", core::to_string(p.session.role)},
                           {"scenario", p.session.scenario},
                           {"channel", p.gyro_channel},
                           {"samples", p.trace->samples.size()}}}}});
      pending.push_back(std::move(p));
      continue;
    }
    auto file = formats::import_file(path, format, options);
    nlohmann::json entry{{"file", path}, {"format", formats::to_string(file.format)}};
    const auto* imported = std::get_if<formats::EventImport>(&file.content);
    std::optional<analysis::LogStamps> log;
    const auto clock =
        imported ? clock_of(*imported, path, log) : std::map<std::string, std::vector<store::ClockSample>>{};
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
    } else if (std::holds_alternative<formats::SyncImport>(file.content)) {
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: a synchronisation-test file holds clock offsets, not edge events: "
                                    "summarise it with `m2mlat stats {}`",
                                    path, path));
    } else {
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{}: a {} file holds the full-loop rig's results, not one board's edges: "
                                    "summarise it with `m2mlat stats {}`",
                                    path, formats::to_string(file.format), path));
    }
    if (events.empty()) throw core::Error(core::ErrorKind::data, fmt::format("{}: no events", path));
    for (const auto& [node, samples] : clock) analysis::flag_events_after_steps(events, node, samples);
    auto sessions = sessions_of(c, path, file.format, std::move(events));
    for (auto& s : sessions)
      if (const auto it = clock.find(s.session.node); it != clock.end()) s.clock = it->second;
    entry["sessions"] = nlohmann::json::array();
    for (std::size_t k = 0; k < sessions.size(); ++k) {
      sessions[k].report_file = report.size();
      sessions[k].report_entry = k;
    }
    for (const auto& s : sessions)
      entry["sessions"].push_back({{"node", s.session.node},
                                   {"role", core::to_string(s.session.role)},
                                   {"scenario", s.session.scenario},
                                   {"events", s.events.size()}});
    report.push_back(entry);
    if (log && sessions.size() == 1) logs.emplace(pending.size(), std::move(*log));  // a kernel log has one node
    std::move(sessions.begin(), sessions.end(), std::back_inserter(pending));
  }

  if (!c.clock_log.empty()) {
    // chronyd's steps go with the node's sessions of this import, or into one of their own.
    auto [steps, failed] = chrony_steps(c.clock_log);
    nlohmann::json entry{{"file", c.clock_log}, {"format", "chrony-log"}, {"steps", steps.size()}, {"failed_steps", failed}};
    bool placed = false;
    for (auto& p : pending)
      if (p.session.node == c.node) {
        p.clock.insert(p.clock.end(), steps.begin(), steps.end());
        analysis::flag_events_after_steps(p.events, p.session.node, p.clock);
        placed = true;
      }
    if (!placed && !steps.empty()) {
      PendingSession p;
      p.session.node = c.node;
      p.session.role = role_for(c, c.node);
      p.session.label = c.label;
      p.session.scenario =
          c.scenario.empty() ? std::filesystem::path(c.clock_log).stem().string() : c.scenario;
      p.session.config_json = nlohmann::json{{"source", "import"}, {"file", c.clock_log}, {"format", "chrony-log"}}
                                  .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      p.session.start = steps.front().time;
      p.session.end = steps.back().time;
      p.clock = std::move(steps);
      pending.push_back(std::move(p));
    }
    entry["node"] = c.node;
    clock_logs.push_back(entry);
  }

  // Then write, all in one transaction: a failed or interrupted import leaves the store as it was.
  const bool existed = std::filesystem::exists(c.store_path);
  try {
    return write_import(c, pending, logs, report, clock_logs);
  } catch (const core::Error&) {
    if (!existed) store::remove_store_files(c.store_path);
    throw;
  }
}

int write_import(const ImportCommand& c, std::vector<PendingSession>& pending,
                 std::map<std::size_t, analysis::LogStamps>& logs, nlohmann::json& report,
                 const nlohmann::json& clock_logs) {
  auto store = store::Store::open(c.store_path);
  store::WholeWrite whole(store);
  std::set<std::string> scenarios;
  std::map<std::int64_t, analysis::LogStamps> stamps;  // the kernel logs', by session id
  for (std::size_t k = 0; k < pending.size(); ++k) {
    auto& p = pending[k];
    if (!p.events.empty()) {
      // A file given twice (or a copy): its events are not stored again.
      const auto held = store::already_stored(store, p.events);
      const auto again = static_cast<std::size_t>(std::count(held.begin(), held.end(), true));
      auto& said = report[p.report_file]["sessions"][p.report_entry];
      said["already_stored"] = again;
      said["events"] = p.events.size() - again;
      if (again == p.events.size()) continue;
      if (again != 0) {
        std::size_t kept = 0;
        for (std::size_t i = 0; i < p.events.size(); ++i)
          if (!held[i]) p.events[kept++] = std::move(p.events[i]);
        p.events.resize(kept);
      }
    }
    const auto end = *p.session.end;
    p.session.end.reset();
    const auto id = store.begin_session(p.session);
    scenarios.insert(p.session.scenario);
    if (const auto it = logs.find(k); it != logs.end()) stamps.emplace(id, std::move(it->second));
    store.append_events(id, p.events);
    for (auto& s : p.clock) s.session_id = id;
    if (!p.clock.empty()) store.append_clock_samples(p.clock);
    if (p.trace)
      store.append_rate_blocks(store::rate_block::split(id, p.gyro_channel, p.trace->clock,
                                                        p.trace->counts_per_deg_s, p.trace->samples));
    store.end_session(id, end);
  }
  // And the steps one board took over from another's (import_follow.hpp), each as a session.
  const auto follow = analysis::take_over_steps(store, scenarios, stamps, "import", c.label);
  whole.commit();
  for (const auto& note : follow.notes) warn(note);
  nlohmann::json followed = nlohmann::json::array();
  for (const auto& f : follow.followed) followed.push_back(analysis::to_json(f));
  if (c.json) {
    nlohmann::json doc{{"store", c.store_path}, {"files", report}};
    if (!clock_logs.empty()) doc["clock_logs"] = clock_logs;
    if (!followed.empty()) doc["followed_steps"] = followed;
    print_json(doc);
  } else {
    for (const auto& f : clock_logs)
      fmt::print("{} (chrony-log): {} clock steps of {}{}\n", core::printable(f["file"].get<std::string>()),
                 f["steps"].get<std::size_t>(), core::printable(f["node"].get<std::string>()),
                 f["failed_steps"].get<std::size_t>() > 0
                     ? fmt::format(" ({} failed steps, not counted)", f["failed_steps"].get<std::size_t>())
                     : "");
    for (const auto& f : report)
      for (const auto& s : f["sessions"])
        if (s.contains("samples"))
          fmt::print("{} ({}): {} samples of {} channel '{}' -> scenario '{}'\n",
                     core::printable(f["file"].get<std::string>()), f["format"].get<std::string>(),
                     s["samples"].get<std::size_t>(), core::printable(s["node"].get<std::string>()),
                     core::printable(s["channel"].get<std::string>()),
                     core::printable(s["scenario"].get<std::string>()));
        else if (s.value("already_stored", std::size_t{0}) != 0 && s["events"].get<std::size_t>() == 0)
          fmt::print("{} ({}): its {} events of {} are already in the store: not imported again\n",
                     core::printable(f["file"].get<std::string>()), f["format"].get<std::string>(),
                     s["already_stored"].get<std::size_t>(), core::printable(s["node"].get<std::string>()));
        else
          fmt::print("{} ({}): {} events of {} ({}) -> scenario '{}'{}\n",
                     core::printable(f["file"].get<std::string>()), f["format"].get<std::string>(),
                     s["events"].get<std::size_t>(), core::printable(s["node"].get<std::string>()),
                     s["role"].get<std::string>(), core::printable(s["scenario"].get<std::string>()),
                     s.value("already_stored", std::size_t{0}) == 0
                         ? std::string{}
                         : fmt::format(" ({} already in the store, not imported again)",
                                       s["already_stored"].get<std::size_t>()));
    for (const auto& f : follow.followed) fmt::print("{}\n", core::printable(analysis::followed_line(f)));
  }
  return 0;
}

}  // namespace

Runner attach_import(CLI::App& sub) {
  auto c = std::make_shared<ImportCommand>();
  sub.add_option("files", c->files, "Files to import ('-' = standard input)");
  sub.add_option("--store", c->store_path, "Store to import into (created if missing)")->required();
  sub.add_option("--format", c->format,
                 "Input format (default: detected): kernel-log, rig-export-csv, "
                 "rig-paired-csv, events-csv, events-jsonl, gyro (an m2mlat-gyro/1 raw trace)");
  sub.add_option("--node", c->node, "Node of formats that name none (kernel log, export CSV)")
      ->capture_default_str();
  sub.add_option("--channel", c->channel,
                 "Channel of those events (default gpio<pin>), or of a gyroscope trace (default gyro)");
  sub.add_option("--line", c->line, "Only this GPIO pin / Line label of a kernel log or export CSV");
  sub.add_option("--role", c->role,
                 "Role of the imported node: cause/operator, effect/vehicle, observer "
                 "(default: from the node's name)");
  sub.add_option("--scenario", c->scenario, "Scenario of the sessions (default: the file's name)");
  sub.add_option("--label", c->label, "Label of the sessions")->capture_default_str();
  sub.add_option("--clock-log", c->clock_log,
                 "chronyd's log (journalctl -o short-iso-precise): its clock steps go to --node");
  sub.add_flag("--json", c->json, "Print what was imported as JSON");
  return [c] { return run_import(*c); };
}

}  // namespace m2mlat::cli
