// `m2mlat pulse`: the synchronisation test's pulse generator. Toggles an output line every period
// on absolute CLOCK_REALTIME deadlines, optionally at SCHED_FIFO on a chosen core, and records each
// commanded edge (channel "pulse", flag commanded) into a store, so that the boards that capture
// the pulse can be compared with when it was made.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/pulse.hpp"
#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/store/event_writer.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct PulseCommand {
  std::string chip, line, period = "500ms", duration, store_path, node;
  std::uint64_t count = 0;
  int rt_priority = 0, cpu = -1;
  bool json = false, quiet = false;
};

int run_pulse(const PulseCommand& c) {
  if (c.store_path.empty() != c.node.empty())
    throw core::Error(core::ErrorKind::usage,
                      "--store and --node go together (the node the pulse events belong to)");
  capture::PulseOptions options;
  options.chip = c.chip;
  options.line = c.line;
  options.period = core::parse_duration(c.period, 1'000'000);
  options.count = c.count;
  if (!c.duration.empty()) options.duration = core::parse_duration(c.duration);
  auto devices = capture::linux_gpio_devices();
  capture::PulseGenerator generator(*devices, options);
  if (!c.quiet) fmt::print(stderr, "m2mlat: pulse: {}\n", generator.describe());

  std::optional<store::Store> store;
  std::unique_ptr<store::EventWriter> writer;
  std::int64_t session_id = 0;
  if (!c.store_path.empty()) {
    store.emplace(store::Store::open(c.store_path));
    store::Session session;
    session.node = c.node;
    session.role = core::Role::observer;
    session.label = "pulse";
    session.scenario = "sync-test";
    session.start = core::realtime_now();
    session.config_json =
        nlohmann::json{
            {"source", "pulse"}, {"chip", c.chip}, {"line", c.line}, {"period_ns", options.period.count()}}
            .dump();
    session_id = store->begin_session(session);
    writer = std::make_unique<store::EventWriter>(*store, session_id);
  }

  for (const auto& outcome : {c.cpu >= 0 ? rt::set_cpu_affinity(c.cpu) : rt::Outcome{},
                              c.rt_priority > 0 ? rt::set_fifo_priority(c.rt_priority) : rt::Outcome{}}) {
    if (!outcome.ok)
      warn(outcome.message);
    else if (!outcome.message.empty() && !c.quiet)
      fmt::print(stderr, "m2mlat: {}\n", outcome.message);
  }

  capture::StopSignal stop;
  const auto summary = generator.run(
      stop.fd(),
      [&](const capture::PulseEdge& edge) {
        if (writer) {
          writer->add(capture::commanded_event(c.node, edge));
          writer->poll();
        }
        if (!c.quiet)
          progress(fmt::format("pulse: {} edges, last {} ({} after its deadline)", edge.index + 1,
                               core::format_seconds(edge.commanded.ns()),
                               core::format_duration(edge.commanded - edge.deadline)));
      },
      [&] { return stop.take(); });
  progress_done();
  if (writer) {
    writer->flush();
    store->end_session(session_id, core::realtime_now());
  }
  const auto mean_late =
      summary.edges > 0 ? summary.total_late / static_cast<std::int64_t>(summary.edges) : core::Duration{0};
  if (c.json) {
    nlohmann::json j{{"edges", summary.edges},
                     {"period_ns", options.period.count()},
                     {"max_late_ns", summary.max_late.count()},
                     {"mean_late_ns", mean_late.count()},
                     {"stop_reason", summary.stop_reason}};
    if (store) {
      j["store"] = c.store_path;
      j["session"] = session_id;
    }
    print_json(j);
  } else {
    fmt::print(
        "pulse: {} edges every {}, stopped by {}; commanded after the deadline by {} on average, {} at "
        "most\n",
        summary.edges, core::format_duration(options.period), summary.stop_reason,
        core::format_duration(mean_late), core::format_duration(summary.max_late));
    if (store)
      fmt::print("{}: session {} (node {}, channel pulse)\n", core::printable(c.store_path), session_id,
                 core::printable(c.node));
  }
  return 0;
}

}  // namespace

Runner attach_pulse(CLI::App& sub) {
  auto c = std::make_shared<PulseCommand>();
  sub.add_option("--chip", c->chip, "Chip: path, name or label")->required();
  sub.add_option("--line", c->line, "Output line: offset or name")->required();
  sub.add_option("--period", c->period, "Time between two edges (a toggle each period)")
      ->capture_default_str();
  auto* count = sub.add_option("--count", c->count, "Number of edges");
  sub.add_option("--duration", c->duration, "Stop after this long")->excludes(count);
  sub.add_option("--rt-priority", c->rt_priority, "SCHED_FIFO priority 1..99");
  sub.add_option("--cpu", c->cpu, "Run on this CPU");
  sub.add_option("--store", c->store_path, "Record the commanded edges into this store (with --node)");
  sub.add_option("--node", c->node, "Node name of the recorded edges");
  sub.add_flag("--quiet", c->quiet, "No progress on stderr");
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  return [c] { return run_pulse(*c); };
}

}  // namespace m2mlat::cli
