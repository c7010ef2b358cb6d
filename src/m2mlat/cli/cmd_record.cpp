// `m2mlat record`: one node's recorder. Reads edges from a capture source (the GPIO character
// device, the reference module's kernel log, or the simulated rig), filters bounces, and writes
// events and losses durably into the store until SIGINT/SIGTERM, a count or a duration; then prints
// a summary per channel (events, suppressed bounces, losses).
#include <fmt/format.h>

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "m2mlat/capture/channel.hpp"
#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/capture/gpio_source.hpp"
#include "m2mlat/capture/kmsg_source.hpp"
#include "m2mlat/capture/record_config.hpp"
#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/sim_source.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/rt/irq.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct RecordCommand {
  std::string store_path, node, role, scenario, label, config_path, source;
  std::vector<std::string> channels;
  std::string edges = "falling", bias = "as-is", clock = "realtime", refractory = "0", debounce = "0";
  bool active_low = false;
  std::uint64_t count = 0;
  std::string duration;
  std::int64_t batch = 512;
  std::string commit_interval = "100ms", durability = "normal";
  int rt_priority = 0, cpu = -1, irq_cpu = -1;
  bool mlock = false, quiet = false, json = false;
  std::string kmsg = "/dev/kmsg", sim_preset = "static_wifi";
  bool sim_paced = false;
  std::uint32_t event_buffer_size = capture::kMaxEventBufferSize;
  // Which of the flags above were given (a flag overrides the file; a file's channel key overrides
  // the flag's default).
  std::map<std::string, CLI::Option*> options;
  bool given(const std::string& name) const { return options.at(name)->count() > 0; }
};

// The channel settings a flag gives, applied where the file did not set the key.
void apply_flags(const RecordCommand& c, capture::ChannelSpec& spec, const std::set<std::string>& file_keys) {
  const auto use = [&](const char* key, const char* flag) {
    return file_keys.count(key) == 0 && c.given(flag);
  };
  if (use("edges", "--edges")) spec.edges = capture::parse_edges(c.edges);
  if (use("bias", "--bias")) spec.bias = capture::parse_bias(c.bias);
  if (use("active_low", "--active-low")) spec.active_low = c.active_low;
  if (use("clock", "--clock")) spec.clock = capture::parse_event_clock(c.clock);
  if (use("refractory", "--refractory")) spec.refractory = core::parse_duration(c.refractory, 1'000'000);
  if (use("debounce", "--debounce")) spec.debounce = core::parse_duration(c.debounce, 1'000'000);
}

nlohmann::json channel_json(const capture::ChannelSpec& s) {
  return {{"name", s.name},
          {"chip", s.chip},
          {"line", s.line},
          {"edges", capture::to_string(s.edges)},
          {"bias", capture::to_string(s.bias)},
          {"active_low", s.active_low},
          {"clock", capture::to_string(s.clock)},
          {"debounce_ns", s.debounce.count()},
          {"refractory_ns", s.refractory.count()}};
}

void print_counters(const capture::RecordCounters& counters) {
  std::string line;
  for (const auto& ch : counters.channels)
    line += fmt::format("{}: {} events, {} suppressed, {} lost, last {}   ", ch.channel, ch.events,
                        ch.suppressed, ch.lost, ch.last ? core::format_seconds(ch.last->ns()) : "-");
  if (counters.node_lost > 0) line += fmt::format("node: {} lost", counters.node_lost);
  progress(line);
}

// Real-time settings, each reported; a refusal is a warning, not a failure of the recording.
void apply_rt(const RecordCommand& c, int priority, int cpu, bool mlock, int irq_cpu,
              const std::vector<std::string>& consumers) {
  const auto report = [&](const rt::Outcome& outcome) {
    if (!outcome.ok)
      warn(outcome.message);
    else if (!c.quiet)
      fmt::print(stderr, "m2mlat: {}\n", outcome.message);
  };
  if (mlock) report(rt::lock_memory());
  if (cpu >= 0) report(rt::set_cpu_affinity(cpu));
  if (priority > 0) report(rt::set_fifo_priority(priority));
  if (irq_cpu >= 0) {
    if (consumers.empty()) warn("--irq-cpu applies to the gpio source only");
    for (const auto& consumer : consumers) {
      const auto irqs = rt::find_irq_by_consumer(consumer);
      if (irqs.empty())
        warn(fmt::format("no interrupt named '{}' in /proc/interrupts: cannot pin it", consumer));
      for (int irq : irqs) report(rt::pin_irq(irq, irq_cpu));
    }
  }
}

int run_record(RecordCommand& c) {
  capture::RecordConfig file;
  if (!c.config_path.empty()) file = capture::load_record_config(c.config_path);

  const auto pick = [&](const std::string& flag, const std::string& value,
                        const std::optional<std::string>& from_file, const std::string& fallback) {
    if (c.given(flag)) return value;
    return from_file ? *from_file : fallback;
  };
  const auto node = pick("--node", c.node, file.node, "");
  if (node.empty())
    throw core::Error(core::ErrorKind::usage, "say which node records: --node NAME (or node = in --config)");
  if (c.store_path.empty()) throw core::Error(core::ErrorKind::usage, "say where events go: --store FILE");
  const auto role = c.given("--role") ? core::parse_role(c.role) : file.role.value_or(core::Role::observer);
  const auto source_kind = pick("--source", c.source, file.source, "gpio");
  if (source_kind != "gpio" && source_kind != "kmsg" && source_kind != "sim")
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("--source '{}': use gpio, kmsg or sim", source_kind));

  std::vector<capture::ChannelSpec> channels;
  for (std::size_t i = 0; i < file.channels.size(); ++i) {
    auto spec = file.channels[i];
    apply_flags(c, spec, file.channel_keys[i]);
    channels.push_back(spec);
  }
  for (const auto& text : c.channels) {
    auto spec = capture::parse_channel_flag(text);
    apply_flags(c, spec, {});
    channels.push_back(spec);
  }

  const auto batch = c.given("--batch") ? c.batch : file.batch.value_or(c.batch);
  if (batch < 1) throw core::Error(core::ErrorKind::usage, "--batch must be at least 1");
  const auto commit_interval = c.given("--commit-interval")
                                   ? core::parse_duration(c.commit_interval, 1'000'000)
                                   : file.commit_interval.value_or(core::parse_duration(c.commit_interval));
  store::Options store_options;
  store_options.durability =
      store::parse_durability(pick("--durability", c.durability, file.durability, "normal"));
  const int priority = c.given("--rt-priority") ? c.rt_priority : file.rt_priority.value_or(0);
  const int cpu = c.given("--cpu") ? c.cpu : file.cpu.value_or(-1);
  const int irq_cpu = c.given("--irq-cpu") ? c.irq_cpu : file.irq_cpu.value_or(-1);
  const bool mlock = c.mlock || file.mlock.value_or(false);

  // The source first: a wrong line or a missing permission should fail before the store is touched.
  std::unique_ptr<capture::Source> source;
  std::unique_ptr<capture::GpioDevices> devices;
  std::vector<std::string> consumers;
  if (source_kind == "gpio") {
    devices = capture::linux_gpio_devices();
    auto gpio = std::make_unique<capture::GpioSource>(
        *devices, channels, capture::GpioSourceOptions{node, "m2mlat-", c.event_buffer_size});
    for (const auto& w : gpio->warnings()) warn(w);
    consumers = gpio->consumers();
    source = std::move(gpio);
  } else if (source_kind == "kmsg") {
    source = std::make_unique<capture::KmsgSource>(
        capture::KmsgSourceOptions{node, pick("--kmsg", c.kmsg, file.kmsg, "/dev/kmsg"), channels});
  } else {
    capture::SimSourceOptions sim;
    sim.node = node;
    if (!channels.empty()) sim.channel = channels.front().name;
    sim.side = role == core::Role::cause ? core::Role::cause : core::Role::effect;
    sim.config = sim::preset(c.sim_preset);
    sim.paced = c.sim_paced;
    source = std::make_unique<capture::SimSource>(std::move(sim));
  }
  if (!c.quiet)
    for (const auto& line : source->describe()) fmt::print(stderr, "m2mlat: {}\n", line);

  capture::RecorderOptions options;
  options.session.node = node;
  options.session.role = role;
  options.session.label = pick("--label", c.label, file.label, "");
  options.session.scenario = pick("--scenario", c.scenario, file.scenario, "");
  nlohmann::json config{{"source", source_kind}, {"channels", nlohmann::json::array()}};
  for (const auto& spec : channels) {
    config["channels"].push_back(channel_json(spec));
    options.refractory[spec.name] = spec.refractory;
  }
  if (!c.config_path.empty()) config["config_file"] = c.config_path;
  if (source_kind == "sim") config["sim_preset"] = c.sim_preset;
  options.session.config_json = config.dump();
  options.batch = static_cast<std::size_t>(batch);
  options.commit_interval = commit_interval;
  options.max_events = c.count;
  if (!c.duration.empty()) options.max_duration = core::parse_duration(c.duration);
  if (!c.quiet && stderr_is_terminal()) options.on_progress = print_counters;

  auto store = store::Store::open(c.store_path, store_options);
  apply_rt(c, priority, cpu, mlock, irq_cpu, consumers);
  capture::StopSignal stop;
  capture::Recorder recorder(store, *source, options);
  const auto counters = recorder.run(stop.fd(), [&] { return stop.take(); });
  progress_done();
  for (const auto& note : source->notes()) warn(note);

  if (c.json) {
    nlohmann::json j{{"store", c.store_path},
                     {"session", counters.session_id},
                     {"node", node},
                     {"role", core::to_string(role)},
                     {"source", source_kind},
                     {"stop_reason", counters.stop_reason},
                     {"events", counters.events},
                     {"node_losses", counters.node_lost},
                     {"last_committed_seq", counters.last_committed_seq},
                     {"channels", nlohmann::json::array()}};
    for (const auto& ch : counters.channels) {
      nlohmann::json row{
          {"channel", ch.channel}, {"events", ch.events}, {"suppressed", ch.suppressed}, {"losses", ch.lost}};
      row["last_ns"] = ch.last ? nlohmann::json(ch.last->ns()) : nlohmann::json(nullptr);
      j["channels"].push_back(row);
    }
    print_json(j);
  } else {
    fmt::print("{}: session {} of node {} ({}), {} events, stopped by {}\n", c.store_path,
               counters.session_id, node, core::to_string(role), counters.events, counters.stop_reason);
    fmt::print("  {:<16} {:>10} {:>10} {:>8}  {}\n", "channel", "events", "suppressed", "losses",
               "last timestamp");
    for (const auto& ch : counters.channels)
      fmt::print("  {:<16} {:>10} {:>10} {:>8}  {}\n", ch.channel, ch.events, ch.suppressed, ch.lost,
                 ch.last ? core::format_seconds(ch.last->ns()) : "-");
    if (counters.node_lost > 0) fmt::print("  {} kernel-log records lost (node-wide)\n", counters.node_lost);
  }
  return 0;
}

}  // namespace

Runner attach_record(CLI::App& sub) {
  auto c = std::make_shared<RecordCommand>();
  auto& o = c->options;
  o["--store"] = sub.add_option("--store", c->store_path, "The store to record into (created if missing)");
  o["--node"] = sub.add_option("--node", c->node, "This board's name, e.g. vehicle");
  o["--role"] = sub.add_option("--role", c->role, "cause (operator), effect (vehicle) or observer");
  o["--scenario"] = sub.add_option("--scenario", c->scenario, "Scenario of the session (free text)");
  o["--label"] = sub.add_option("--label", c->label, "Label of the session (free text)");
  o["--config"] = sub.add_option("--config", c->config_path, "TOML configuration (docs/capture.md)");
  o["--source"] = sub.add_option("--source", c->source, "gpio (default), kmsg or sim");
  o["--channel"] = sub.add_option("--channel", c->channels,
                                  "NAME=CHIP:LINE (repeatable); CHIP path/name/label, LINE offset or name");
  o["--edges"] = sub.add_option("--edges", c->edges, "falling, rising or both")->capture_default_str();
  o["--bias"] =
      sub.add_option("--bias", c->bias, "as-is, pull-up, pull-down or disabled")->capture_default_str();
  o["--active-low"] = sub.add_flag("--active-low", c->active_low, "The line is active low");
  o["--clock"] =
      sub.add_option("--clock", c->clock, "Event clock: realtime, monotonic or hte")->capture_default_str();
  o["--refractory"] =
      sub.add_option("--refractory", c->refractory, "Drop edges this soon after a kept one (e.g. 10ms)")
          ->capture_default_str();
  o["--debounce"] =
      sub.add_option("--debounce", c->debounce, "Kernel debounce (makes timestamps late; default none)")
          ->capture_default_str();
  o["--count"] = sub.add_option("--count", c->count, "Stop after N stored events");
  o["--duration"] = sub.add_option("--duration", c->duration, "Stop after this long (e.g. 10min)");
  o["--batch"] = sub.add_option("--batch", c->batch, "Events per commit")->capture_default_str();
  o["--commit-interval"] =
      sub.add_option("--commit-interval", c->commit_interval, "Longest an event waits for its commit")
          ->capture_default_str();
  o["--durability"] = sub.add_option("--durability", c->durability, "full, normal or off (docs/store.md)")
                          ->capture_default_str();
  o["--rt-priority"] = sub.add_option("--rt-priority", c->rt_priority, "SCHED_FIFO priority 1..99");
  o["--cpu"] = sub.add_option("--cpu", c->cpu, "Run on this CPU");
  o["--mlock"] = sub.add_flag("--mlock", c->mlock, "Lock the process's memory");
  o["--irq-cpu"] = sub.add_option("--irq-cpu", c->irq_cpu, "Route each line's interrupt to this CPU (root)");
  o["--kmsg"] = sub.add_option("--kmsg", c->kmsg, "kmsg source: /dev/kmsg or a log file to follow")
                    ->capture_default_str();
  o["--sim-preset"] = sub.add_option("--sim-preset", c->sim_preset, "sim source: the simulated rig's preset")
                          ->capture_default_str();
  o["--sim-paced"] = sub.add_flag("--sim-paced", c->sim_paced, "sim source: hand events over in real time");
  sub.add_option("--event-buffer-size", c->event_buffer_size,
                 "gpio source: events the kernel buffers per line (1..1024; smaller only for loss tests)")
      ->check(CLI::Range(1u, capture::kMaxEventBufferSize))
      ->capture_default_str();
  sub.add_flag("--quiet", c->quiet, "No settings or live counters on stderr");
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  return [c] { return run_record(*c); };
}

}  // namespace m2mlat::cli
