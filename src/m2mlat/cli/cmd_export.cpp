// `m2mlat export`: a store's events, the pairs recomputed from them, a gyroscope's raw trace, or its
// markers, as files.
#include <fmt/format.h>

#include <fmt/ranges.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/analysis/clock_records.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/pair_sessions.hpp"
#include "m2mlat/analysis/pairs_file.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/rate_trace_csv.hpp"
#include "m2mlat/markers/markers_file.hpp"
#include "m2mlat/markers/stored_markers.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct ExportCommand {
  std::string store_path;
  std::string what = "events";
  std::string out = "-";
  std::string format;
  std::vector<std::string> scenarios;
  std::string node;
  std::string channel;
  std::int64_t session = 0;
  bool with_meta = false;
  SelectionFlags selection;
  MatchFlags match;
};

// One stored raw trace as an m2mlat-gyro/1 file. The trace is chosen by --session, --node, --channel
// and --scenario; more than one left is a usage error listing them. The comment lines an imported
// file had (kept in its session's configuration) are written back with it.
int export_gyro(const ExportCommand& c) {
  store::Options options;
  options.read_only = true;
  auto store = store::Store::open(c.store_path, options);
  std::vector<std::pair<store::RateChannel, store::Session>> found;
  for (const auto& trace : store.rate_channels()) {
    const auto session = store.session(trace.session_id);
    if (!session) continue;  // a dangling session id: check_rows reports it
    if (c.session != 0 && trace.session_id != c.session) continue;
    if (!c.node.empty() && trace.node != c.node) continue;
    if (!c.channel.empty() && trace.channel != c.channel) continue;
    if (!c.scenarios.empty() &&
        std::find(c.scenarios.begin(), c.scenarios.end(), session->scenario) == c.scenarios.end())
      continue;
    found.emplace_back(trace, *session);
  }
  if (found.empty())
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{}: no raw gyroscope trace matches (see --session, --node, --channel)",
                                  c.store_path));
  if (found.size() > 1) {
    std::vector<std::string> names;
    for (const auto& [t, s] : found)
      names.push_back(fmt::format("session {} node '{}' channel '{}'", t.session_id, t.node, t.channel));
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{} holds {} matching raw traces ({}): choose one with --session, --node or "
                                  "--channel",
                                  c.store_path, found.size(), fmt::join(names, "; ")));
  }
  const auto& [chosen, session] = found.front();
  const core::RateTrace trace = store.rate_trace(chosen.session_id, chosen.channel);
  std::vector<std::string> comments;
  const auto config = nlohmann::json::parse(session.config_json, nullptr, false);
  if (config.is_object() && config.contains("comments") && config["comments"].is_array())
    for (const auto& line : config["comments"])
      if (line.is_string()) comments.push_back(line.get<std::string>());
  core::write_output_file(c.out, [&](std::ostream& os) { formats::write_rate_trace_csv(os, trace, comments); });
  return 0;
}

// The store's markers (software markers, markers read from bags) as m2mlat-markers/1 CSV, in time
// order, optionally of some scenarios' sessions and one node.
int export_markers(const ExportCommand& c) {
  if (!c.format.empty() && c.format != "markers-csv")
    throw core::Error(core::ErrorKind::usage, fmt::format("--format '{}': --what markers writes markers-csv",
                                                          c.format));
  store::Options options;
  options.read_only = true;
  auto store = store::Store::open(c.store_path, options);
  std::vector<markers::Marker> selected;
  if (c.scenarios.empty()) {
    selected = markers::store_markers(store);
  } else {
    for (const auto& scenario : c.scenarios)
      for (auto& m : markers::store_markers(store, scenario)) selected.push_back(std::move(m));
    std::stable_sort(selected.begin(), selected.end(),
                     [](const markers::Marker& a, const markers::Marker& b) { return a.time < b.time; });
  }
  if (!c.node.empty())
    std::erase_if(selected, [&](const markers::Marker& m) { return m.node != c.node; });
  core::write_output_file(c.out, markers::markers_csv(selected));
  return 0;
}

int run_export(const ExportCommand& c) {
  if (c.what == "pairs") {
    StatsFlags no_bootstrap;
    no_bootstrap.bootstrap = 0;
    const auto pipeline = pipeline_options(c.selection, c.match, no_bootstrap);
    analysis::PipelineInputs inputs;
    inputs.inputs = {c.store_path};
    inputs.scenarios = c.scenarios;
    const auto results = analysis::analyse_inputs(inputs, pipeline);
    for (const auto& r : results)  // the sanity verdict: the file holds the pairs, stderr says what is wrong
      for (const auto& w : r.warnings) warn(fmt::format("{}: {}", r.input.scenario, w.text));
    const auto format = formats::parse_format(c.format.empty() ? "pairs-csv" : c.format);
    analysis::write_pairs_file(c.out, format, results, analysis::store_pair_sessions(c.store_path, results));
    return 0;
  }
  if (c.what == "gyro") return export_gyro(c);
  if (c.what == "markers") return export_markers(c);
  if (c.what != "events") throw core::Error(core::ErrorKind::usage, "--what: events, pairs, gyro or markers");

  store::Options options;
  options.read_only = true;
  auto store = store::Store::open(c.store_path, options);
  std::vector<core::Event> events;
  std::vector<formats::EventOrigin> origins;  // one run of events per session
  std::vector<formats::ClockRecord> clocks;   // the sessions' clock samples and steps, carried along
  for (const auto& session : store.sessions()) {
    if (!c.scenarios.empty() &&
        std::find(c.scenarios.begin(), c.scenarios.end(), session.scenario) == c.scenarios.end())
      continue;
    if (!c.node.empty() && session.node != c.node) continue;
    // Every event of the session, in time order.
    store::EventFilter filter;
    filter.session_id = session.id;
    const std::size_t before = events.size();
    for (auto clock :
         {core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime, core::Clock::simulated})
      for (auto& e : store.events_in_time(
               core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::min()),
               core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::max()), filter))
        events.push_back(std::move(e.event));
    origins.push_back({session.scenario, session.id, session.label, events.size() - before});
    for (const auto& s : store.clock_samples(session.id)) clocks.push_back(analysis::to_clock_record(s, session.node));
  }
  const auto format = formats::parse_format(c.format.empty() ? "events-csv" : c.format);
  formats::EventExportOptions how{.clocks = clocks, .origins = origins, .with_meta = c.with_meta};
  formats::export_events(c.out, format, events, how);
  // A plain CSV has no place for the clock records: say what was left out and how to keep it.
  if (format == formats::Format::events_csv && !c.with_meta && !clocks.empty())
    fmt::print(stderr,
               "note: {} clock samples of the boards are not in the CSV (a plain table); --with-meta writes "
               "them before its header, for `m2mlat import` (or use --format events-jsonl)\n",
               clocks.size());
  return 0;
}

}  // namespace

Runner attach_export(CLI::App& sub) {
  auto c = std::make_shared<ExportCommand>();
  sub.add_option("store", c->store_path, "The store to export from")->required();
  sub.add_option("--what", c->what,
                 "events, pairs (recomputed by the matcher), gyro (one raw trace as m2mlat-gyro/1), or markers "
                 "(m2mlat-markers/1)")
      ->capture_default_str();
  sub.add_option("-o,--out", c->out, "Output file ('-' = standard output)")->capture_default_str();
  sub.add_option("--format", c->format,
                 "events-csv (default), events-jsonl; pairs-csv (default), pairs-jsonl, rig-paired-csv; markers-csv");
  sub.add_option("--scenario", c->scenarios, "Only these scenarios (repeatable; default: all)");
  sub.add_flag("--with-meta", c->with_meta,
               "events-csv: the format line and the boards' clock records as '#' lines before the header "
               "(for `m2mlat import`; pandas then needs comment='#')");
  sub.add_option("--node", c->node, "Only the events (or raw trace, or markers) of this node");
  sub.add_option("--channel", c->channel, "--what gyro: the trace's channel");
  sub.add_option("--session", c->session, "--what gyro: the trace's session id");
  c->selection.add_to(sub);
  c->match.add_to(sub);
  return [c] { return run_export(*c); };
}

}  // namespace m2mlat::cli
