// `m2mlat export`: a store's events, or the pairs recomputed from them, as files.
#include <fmt/format.h>

#include <limits>
#include <memory>

#include "m2mlat/analysis/clock_records.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/pairs_file.hpp"
#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
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
  SelectionFlags selection;
  MatchFlags match;
};

int run_export(const ExportCommand& c) {
  if (c.what == "pairs") {
    StatsFlags no_bootstrap;
    no_bootstrap.bootstrap = 0;
    const auto pipeline = pipeline_options(c.selection, c.match, no_bootstrap);
    analysis::PipelineInputs inputs;
    inputs.inputs = {c.store_path};
    inputs.scenarios = c.scenarios;
    const auto results = analysis::analyse_inputs(inputs, pipeline);
    if (results.size() != 1)
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("{} has {} scenarios: export the pairs of one with --scenario",
                                    c.store_path, results.size()));
    const auto format = formats::parse_format(c.format.empty() ? "pairs-csv" : c.format);
    analysis::write_pairs_file(c.out, format, results);
    return 0;
  }
  if (c.what != "events") throw core::Error(core::ErrorKind::usage, "--what: events or pairs");

  store::Options options;
  options.read_only = true;
  auto store = store::Store::open(c.store_path, options);
  std::vector<core::Event> events;
  std::vector<formats::ClockRecord> clocks;  // the sessions' clock samples and steps, carried along
  for (const auto& session : store.sessions()) {
    if (!c.scenarios.empty() &&
        std::find(c.scenarios.begin(), c.scenarios.end(), session.scenario) == c.scenarios.end())
      continue;
    if (!c.node.empty() && session.node != c.node) continue;
    // Every event of the session, in time order.
    store::EventFilter filter;
    filter.session_id = session.id;
    for (auto clock :
         {core::Clock::realtime, core::Clock::monotonic, core::Clock::boottime, core::Clock::simulated})
      for (auto& e : store.events_in_time(
               core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::min()),
               core::TimePoint::from_ns(clock, std::numeric_limits<std::int64_t>::max()), filter))
        events.push_back(std::move(e.event));
    for (const auto& s : store.clock_samples(session.id)) clocks.push_back(analysis::to_clock_record(s, session.node));
  }
  formats::export_events(c.out, formats::parse_format(c.format.empty() ? "events-csv" : c.format), events,
                         clocks);
  return 0;
}

}  // namespace

Runner attach_export(CLI::App& sub) {
  auto c = std::make_shared<ExportCommand>();
  sub.add_option("store", c->store_path, "The store to export from")->required();
  sub.add_option("--what", c->what, "events, or pairs (recomputed by the matcher)")->capture_default_str();
  sub.add_option("-o,--out", c->out, "Output file ('-' = standard output)")->capture_default_str();
  sub.add_option("--format", c->format,
                 "events-csv (default), events-jsonl; pairs-csv (default), pairs-jsonl, rig-paired-csv");
  sub.add_option("--scenario", c->scenarios, "Only these scenarios (repeatable)");
  sub.add_option("--node", c->node, "Only the events of this node");
  c->selection.add_to(sub);
  c->match.add_to(sub);
  return [c] { return run_export(*c); };
}

}  // namespace m2mlat::cli
