// `m2mlat led`: the glass-to-glass LED. Switches an output line (the LED in the camera's view) on a
// schedule, on commands (lines on stdin, UDP datagrams), at each edge of an input line (the
// vehicle's motion onset) or at each motion onset a gyroscope's streaming detector finds, and records every switch (channel "led", flag commanded, its time the
// middle of the clock readings just before and just after the ioctl) into a store and/or an events
// file, so that `stats --cause vehicle/led --effect operator/photo` gives glass-to-glass latency.
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/gyro_trigger.hpp"
#include "m2mlat/capture/led_trigger.hpp"
#include "m2mlat/capture/pulse.hpp"
#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/cli/record_setup.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/events_csv.hpp"
#include "m2mlat/formats/events_jsonl.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/store/event_writer.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct LedCommand {
  std::string chip, line, channel = "led", period, on_for = "100ms", duration, listen, on_edge, on_gyro;
  std::string gyro_period = "1ms";
  std::string edges = "falling", bias = "as-is";
  std::string store_path, events_path, node, scenario = "g2g", role = "cause";
  std::uint64_t count = 0;
  int rt_priority = 0, cpu = -1;
  bool from_stdin = false, json = false, quiet = false;
};

// The largest and the mean ioctl bound of the switches (PulseEdge::bound), ns.
struct BoundTally {
  std::uint64_t n = 0;
  core::Duration max{0}, total{0};
  void add(const capture::PulseEdge& e) {
    ++n;
    max = std::max(max, e.bound());
    total += e.bound();
  }
  core::Duration mean() const { return n > 0 ? total / static_cast<std::int64_t>(n) : core::Duration{0}; }
};

int run_led(const LedCommand& c) {
  const int triggers = (c.period.empty() ? 0 : 1) + (c.from_stdin ? 1 : 0) + (c.listen.empty() ? 0 : 1) +
                       (c.on_edge.empty() ? 0 : 1) + (c.on_gyro.empty() ? 0 : 1);
  if (triggers != 1)
    throw core::Error(
        core::ErrorKind::usage,
        "choose one trigger: --period (a schedule), --stdin or --listen (commands), --on-edge "
        "(an input line's edges) or --on-gyro (a gyroscope's motion onsets)");
  if ((!c.store_path.empty() || !c.events_path.empty()) && c.node.empty())
    throw core::Error(core::ErrorKind::usage, "--store and --events need --node (the board the LED is on)");
  if (c.period.empty() && (c.count > 0 || !c.duration.empty()))
    throw core::Error(core::ErrorKind::usage,
                      "--count and --duration go with --period (a schedule); "
                      "a triggered LED runs until its input ends or SIGINT/SIGTERM");
  if (!c.events_path.empty()) core::check_output_target(c.events_path);

  capture::PulseOptions options;
  options.chip = c.chip;
  options.line = c.line;
  options.consumer = "m2mlat-" + c.channel;
  options.on_for = core::parse_duration(c.on_for, 1'000'000);
  if (!c.period.empty()) {
    options.period = core::parse_duration(c.period, 1'000'000);
    options.count = c.count * 2;  // a flash is two edges
    if (!c.duration.empty()) options.duration = core::parse_duration(c.duration);
  }
  auto devices = capture::linux_gpio_devices();
  capture::PulseGenerator led(*devices, options);

  // Before any thread starts (the gyroscope's sampler), so that every thread blocks the signals.
  capture::StopSignal stop;
  std::unique_ptr<capture::LedTrigger> trigger;
  capture::GyroTrigger* gyro = nullptr;
  if (!c.on_gyro.empty()) {
    capture::GyroTriggerOptions go;
    go.period = core::parse_duration(c.gyro_period, 1'000'000);
    if (go.period.count() <= 0) throw core::Error(core::ErrorKind::usage, "--gyro-period: must be positive");
    go.rt_priority = c.rt_priority;
    go.cpu = c.cpu;
    auto opened = open_gyro_bus("--on-gyro", c.on_gyro, 1);
    auto t = std::make_unique<capture::GyroTrigger>(
        std::move(opened.bus), fmt::format("{} address {}", opened.device, opened.address), go);
    gyro = t.get();
    trigger = std::move(t);
  }
  if (c.from_stdin) trigger = capture::stream_trigger(0, "stdin");
  if (!c.listen.empty()) trigger = std::make_unique<capture::DatagramTrigger>(c.listen);
  if (!c.on_edge.empty()) {
    auto spec = capture::parse_channel_flag(c.on_edge);
    spec.edges = capture::parse_edges(c.edges);
    spec.bias = capture::parse_bias(c.bias);
    trigger = capture::edge_trigger(*devices, spec, c.node.empty() ? std::string("led") : c.node);
  }
  std::optional<store::Store> store;
  std::unique_ptr<store::EventWriter> writer;
  std::int64_t session_id = 0;
  if (!c.store_path.empty()) {
    store.emplace(store::Store::open(c.store_path));
    store::Session session;
    session.node = c.node;
    session.role = core::parse_role(c.role);
    session.label = "led";
    session.scenario = c.scenario;
    session.start = core::realtime_now();
    session.config_json = nlohmann::json{{"source", "led"},
                                         {"chip", c.chip},
                                         {"line", c.line},
                                         {"channel", c.channel},
                                         {"on_for_ns", options.on_for.count()},
                                         {"trigger", trigger ? trigger->describe() : "schedule"},
                                         {"event_time", "middle of the clock readings around the ioctl"}}
                              .dump();
    session_id = store->begin_session(session);
    writer = std::make_unique<store::EventWriter>(*store, session_id);
  }
  std::vector<core::Event> kept;  // for the events file
  const auto keep = [&](const core::Event& e) {
    if (writer) {
      writer->add(e);
      writer->poll();
    }
    if (!c.events_path.empty()) kept.push_back(e);
  };

  for (const auto& outcome : {c.cpu >= 0 ? rt::set_cpu_affinity(c.cpu) : rt::Outcome{},
                              c.rt_priority > 0 ? rt::set_fifo_priority(c.rt_priority) : rt::Outcome{}}) {
    if (!outcome.ok)
      warn(outcome.message);
    else if (!outcome.message.empty() && !c.quiet)
      fmt::print(stderr, "m2mlat: {}\n", outcome.message);
  }

  // Said once the store is open and the session begun: from here on an edge or command is answered
  // (a script may wait for this line before it triggers).
  if (!c.quiet)
    fmt::print(stderr, "m2mlat: led: {}; {}\n", led.describe(),
               trigger ? trigger->describe() : std::string("on a schedule"));
  BoundTally bound;
  const auto on_edge = [&](const capture::PulseEdge& edge) {
    bound.add(edge);
    if (!c.node.empty()) keep(capture::led_event(c.node, c.channel, edge));
    if (!c.quiet)
      progress(fmt::format("led: {} switches, last {} {} (ioctl {})", bound.n, core::to_string(edge.edge),
                           core::format_seconds(edge.commanded.ns()), core::format_duration(edge.bound())));
  };
  std::string stop_reason;
  std::uint64_t refused = 0, trigger_edges = 0;
  core::Duration max_late{0};
  if (trigger) {
    const auto summary = capture::run_triggered(
        led, *trigger, options.on_for, stop.fd(), on_edge,
        [&](const capture::TriggerInput& in) {
          for (const auto& e : in.edges) {
            ++trigger_edges;
            if (!c.node.empty()) keep(e);
          }
          for (const auto& r : in.refused) {
            ++refused;
            warn(r);
          }
        },
        [&] { return stop.take(); });
    stop_reason = summary.stop_reason;
  } else {
    const auto summary = led.run(stop.fd(), on_edge, [&] { return stop.take(); });
    stop_reason = summary.stop_reason;
    max_late = summary.max_late;
  }
  progress_done();
  if (writer) {
    writer->flush();
    // The session's configuration gains the largest half-width of its writes: one bound, conservative
    // for every write, that survives merge, ingest and the agent API with the session itself.
    auto config = nlohmann::json::parse(store->session(session_id)->config_json);
    if (bound.n > 0) config[store::kConfigLedBound] = (bound.max - bound.max / 2).count();
    store->end_session(session_id, core::realtime_now(), config.dump());
  }
  if (!c.events_path.empty())
    core::write_output_file(c.events_path, [&](std::ostream& out) {
      if (c.events_path.ends_with(".jsonl"))
        formats::write_events_jsonl(out, kept);
      else
        formats::write_events_csv(out, kept);
    });

  if (c.json) {
    nlohmann::json j{{"switches", bound.n},
                     {"trigger_edges", trigger_edges},
                     {"refused_commands", refused},
                     {"ioctl_max_ns", bound.max.count()},
                     {"ioctl_mean_ns", bound.mean().count()},
                     {"event_error_max_ns", (bound.max / 2).count()},
                     {"stop_reason", stop_reason}};
    if (!trigger) j["max_late_ns"] = max_late.count();
    if (gyro) {
      const auto summary = gyro->summary();
      j["gyro"] = {{"samples", gyro->samples()},
                   {"onsets", gyro->onsets()},
                   {"threshold_deg_s", gyro->threshold_deg_s()},
                   {"missed_periods", summary.missed_periods},
                   {"i2c_errors", summary.i2c_errors}};
    }
    if (store) {
      j["store"] = c.store_path;
      j["session"] = session_id;
    }
    if (!c.events_path.empty()) j["events"] = c.events_path;
    print_json(j);
  } else {
    fmt::print(
        "led: {} switches, stopped by {}; the ioctl took {} on average, {} at most (each event's time "
        "is within +-{} of the switch)\n",
        bound.n, stop_reason, core::format_duration(bound.mean()), core::format_duration(bound.max),
        core::format_duration(bound.max / 2));
    if (store)
      fmt::print("{}: session {} (node {}, channel {}, scenario {})\n", core::printable(c.store_path),
                 session_id, core::printable(c.node), core::printable(c.channel),
                 core::printable(c.scenario));
    if (!c.events_path.empty()) fmt::print("{}: {} events\n", core::printable(c.events_path), kept.size());
    if (gyro)
      fmt::print("gyroscope: {} samples, {} motion onsets (threshold {:.3f} deg/s), {} missed periods\n",
                 gyro->samples(), gyro->onsets(), gyro->threshold_deg_s(), gyro->summary().missed_periods);
  }
  return 0;
}

}  // namespace

Runner attach_led(CLI::App& sub) {
  auto c = std::make_shared<LedCommand>();
  sub.add_option("--chip", c->chip, "Chip of the LED's output line: path, name or label")->required();
  sub.add_option("--line", c->line, "The LED's output line: offset or name")->required();
  sub.add_option("--period", c->period, "Trigger: a flash every period (on multiples of it)");
  sub.add_option("--on-for", c->on_for, "How long a flash keeps the LED on")->capture_default_str();
  auto* count = sub.add_option("--count", c->count, "Schedule: number of flashes");
  sub.add_option("--duration", c->duration, "Schedule: stop after this long")->excludes(count);
  sub.add_flag("--stdin", c->from_stdin, "Trigger: commands on stdin, one a line (on, off, flash)");
  sub.add_option("--listen", c->listen, "Trigger: commands as UDP datagrams on HOST:PORT");
  sub.add_option("--on-edge", c->on_edge, "Trigger: a flash at each edge of an input line, NAME=CHIP:LINE");
  sub.add_option("--on-gyro", c->on_gyro,
                 "Trigger: a flash at each motion onset a gyroscope sees, /dev/i2c-N[:ADDRESS] or sim");
  sub.add_option("--gyro-period", c->gyro_period, "--on-gyro: the gyroscope's read period")
      ->capture_default_str();
  sub.add_option("--edges", c->edges, "--on-edge: falling, rising or both")->capture_default_str();
  sub.add_option("--bias", c->bias, "--on-edge: as-is, pull-up, pull-down or disabled")
      ->capture_default_str();
  sub.add_option("--channel", c->channel, "Channel name of the LED's events")->capture_default_str();
  sub.add_option("--store", c->store_path, "Record the switches into this store (with --node)");
  sub.add_option("--events", c->events_path, "Write the switches to this events file (.csv or .jsonl)");
  sub.add_option("--node", c->node, "Node name of the recorded switches, e.g. vehicle");
  sub.add_option("--scenario", c->scenario, "Scenario of the store's session")->capture_default_str();
  sub.add_option("--role", c->role, "Role of the store's session")->capture_default_str();
  sub.add_option("--rt-priority", c->rt_priority, "SCHED_FIFO priority 1..99");
  sub.add_option("--cpu", c->cpu, "Run on this CPU");
  sub.add_flag("--quiet", c->quiet, "No progress on stderr");
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  return [c] { return run_led(*c); };
}

}  // namespace m2mlat::cli
