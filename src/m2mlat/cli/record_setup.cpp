// Merging the TOML configuration with the flags, opening the source, real-time settings.
#include "m2mlat/cli/record_setup.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <set>

#include "m2mlat/capture/gpio_source.hpp"
#include "m2mlat/capture/kmsg_source.hpp"
#include "m2mlat/capture/record_config.hpp"
#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/sim_gyro.hpp"
#include "m2mlat/capture/sim_source.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/rt/irq.hpp"
#include "m2mlat/rt/scheduling.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

// The channel settings a flag gives, applied where the file did not set the key.
void apply_flags(const RecordFlags& c, capture::ChannelSpec& spec, const std::set<std::string>& file_keys) {
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

// The clock monitor of a real board: its samples go into the same commits as the events.
void start_clock_monitor(const RecordFlags& c, const capture::RecordConfig& file, RecordSetup& s) {
  const auto interval = [&](const char* flag, const std::string& value,
                            const std::optional<core::Duration>& from_file) {
    const auto d = c.given(flag) || !from_file ? core::parse_duration(value, 1'000'000'000) : *from_file;
    if (d.count() < 0) throw core::Error(core::ErrorKind::usage, fmt::format("{} must not be negative", flag));
    return d;
  };
  sync::MonitorOptions mo;
  mo.kernel_interval = interval("--kernel-interval", c.kernel_interval, file.kernel_interval);
  mo.chrony_interval = interval("--chrony-interval", c.chrony_interval, file.chrony_interval);
  mo.ptp_interval = interval("--ptp-interval", c.ptp_interval, file.ptp_interval);
  mo.chronyc.host = c.chronyc_socket;
  mo.pmc.uds = c.pmc_socket;
  s.clocks = std::make_unique<sync::SystemClockSource>();
  s.runner = std::make_unique<process::ProcessRunner>();
  s.monitor = std::make_unique<sync::ClockMonitor>(mo, *s.clocks, s.runner.get());
  s.options.before_commit = [monitor = s.monitor.get()](std::int64_t session,
                                                        std::vector<store::ClockSample>& out) {
    monitor->on_batch(session, out);
  };
}

// --gyro DEVICE[:ADDRESS]: opens and configures the chip (a missing chip or a wrong WHO_AM_I fails
// here, before the store is touched), makes the sampler and the channel, and sets the recorder's
// raw_samples hook. Returns the gyroscope's part of the session's configuration.
nlohmann::json open_gyro(const RecordFlags& c, RecordSetup& s) {
  if (c.gyro_channel.empty()) throw core::Error(core::ErrorKind::usage, "--gyro-channel: must not be empty");
  const auto keep = capture::parse_gyro_keep("--gyro-keep", c.gyro_keep);
  capture::GyroSourceOptions options;
  options.period = duration_flag("--gyro-period", c.gyro_period);
  if (options.period.count() <= 0) throw core::Error(core::ErrorKind::usage, "--gyro-period: must be positive");
  options.chip_output_period = core::Duration{1'000'000'000 / capture::mpu6050::kGyroRateHz};  // divider 0
  options.rt_priority = s.rt_priority;
  options.cpu = s.cpu;

  auto g = std::make_unique<GyroSetup>();
  auto opened = open_gyro_bus("--gyro", c.gyro, c.sim_seed);
  const auto device = opened.device, address = opened.address;
  g->bus = std::move(opened.bus);
  g->chip = std::make_unique<capture::Mpu6050>(*g->bus);
  g->chip->configure({});
  g->source = std::make_unique<capture::GyroSource>(*g->chip, options);
  g->channel = std::make_unique<capture::GyroChannel>(c.gyro_channel, core::Clock::realtime,
                                                      capture::mpu6050::kCountsPerDegS, keep);
  GyroSetup* gyro = g.get();
  const auto period = options.period;
  s.options.raw_samples = [gyro, period](const capture::RawRound& round, std::vector<store::RateBlock>& blocks,
                                         std::vector<store::Loss>& losses) {
    if (round.final) {  // the recorder has stopped: so does the sampler, and all it read goes into this round
      gyro->source->stop();
      gyro->source->join();
    }
    gyro->channel->add(gyro->source->take(), gyro->source->summary());
    if (round.end && gyro->source->running()) {
      // A session ends: wait (three read periods at most) for a sample stamped after its end, so that
      // the one being read at the end goes to this session and not, a straggler, to none.
      for (int i = 0; i < 12 && gyro->channel->newest_ns().value_or(0) <= round.end->ns(); ++i) {
        core::sleep_until_ns(CLOCK_MONOTONIC, core::monotonic_now().count() + period.count() / 4);
        gyro->channel->add(gyro->source->take(), gyro->source->summary());
      }
    }
    gyro->channel->collect(round, core::realtime_now(), blocks, losses);
  };
  nlohmann::json out{{"device", device},
                     {"address", address},
                     {"channel", c.gyro_channel},
                     {"keep", c.gyro_keep},
                     {"period_ns", options.period.count()},
                     {"counts_per_deg_s", capture::mpu6050::kCountsPerDegS}};
  s.gyro = std::move(g);
  return out;
}

}  // namespace

GyroBus open_gyro_bus(const std::string& flag, const std::string& text, std::uint64_t seed) {
  if (text == "sim") return {capture::make_sim_gyro(seed), "sim", "0x68"};
  GyroBus out{nullptr, text, "0x68"};
  if (const auto colon = text.rfind(':'); colon != std::string::npos && text.find('/', colon) == std::string::npos) {
    out.device = text.substr(0, colon);
    out.address = text.substr(colon + 1);
  }
  out.bus = std::make_unique<capture::I2cBus>(out.device, capture::parse_i2c_address(flag, out.address));
  return out;
}

void warn_after_run(const RecordSetup& s) {
  for (const auto& note : s.source->notes()) warn(note);
  if (!s.monitor) return;
  for (const auto* failure : {&s.monitor->chrony_error(), &s.monitor->ptp_error()})
    if (!failure->empty())
      warn(fmt::format("clock monitor: {} (--chrony-interval 0 / --ptp-interval 0 turn a reading off)", *failure));
}

void print_counters(const capture::RecordCounters& counters) {
  std::string line;
  for (const auto& ch : counters.channels)
    line += fmt::format("{}: {} events, {} suppressed, {} lost, last {}   ", ch.channel, ch.events,
                        ch.suppressed, ch.lost, ch.last ? core::format_seconds(ch.last->ns()) : "-");
  if (counters.node_lost > 0) line += fmt::format("node: {} lost", counters.node_lost);
  progress(line);
}

void apply_rt(const RecordSetup& s, bool quiet) {
  const auto report = [&](const rt::Outcome& outcome) {
    if (!outcome.ok)
      warn(outcome.message);
    else if (!quiet)
      fmt::print(stderr, "m2mlat: {}\n", outcome.message);
  };
  if (s.mlock) report(rt::lock_memory());
  if (s.cpu >= 0) report(rt::set_cpu_affinity(s.cpu));
  if (s.rt_priority > 0) report(rt::set_fifo_priority(s.rt_priority));
  if (s.irq_cpu >= 0) {
    if (s.consumers.empty()) warn("--irq-cpu applies to the gpio source only");
    for (const auto& consumer : s.consumers) {
      const auto irqs = rt::find_irq_by_consumer(consumer);
      if (irqs.empty())
        warn(fmt::format("no interrupt named '{}' in /proc/interrupts: cannot pin it", consumer));
      for (int irq : irqs) report(rt::pin_irq(irq, s.irq_cpu));
    }
  }
}

RecordSetup prepare_record(const RecordFlags& c) {
  capture::RecordConfig file;
  if (!c.config_path.empty()) file = capture::load_record_config(c.config_path);

  const auto pick = [&](const std::string& flag, const std::string& value,
                        const std::optional<std::string>& from_file, const std::string& fallback) {
    if (c.given(flag)) return value;
    return from_file ? *from_file : fallback;
  };
  RecordSetup s;
  s.node = pick("--node", c.node, file.node, "");
  if (s.node.empty())
    throw core::Error(core::ErrorKind::usage, "say which node records: --node NAME (or node = in --config)");
  if (c.store_path.empty()) throw core::Error(core::ErrorKind::usage, "say where events go: --store FILE");
  s.role = c.given("--role") ? core::parse_role(c.role) : file.role.value_or(core::Role::observer);
  s.source_kind = pick("--source", c.source, file.source, "gpio");
  if (s.source_kind != "gpio" && s.source_kind != "kmsg" && s.source_kind != "sim")
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("--source '{}': use gpio, kmsg or sim", s.source_kind));

  for (std::size_t i = 0; i < file.channels.size(); ++i) {
    auto spec = file.channels[i];
    apply_flags(c, spec, file.channel_keys[i]);
    s.channels.push_back(spec);
  }
  for (const auto& text : c.channels) {
    auto spec = capture::parse_channel_flag(text);
    apply_flags(c, spec, {});
    s.channels.push_back(spec);
  }

  const auto batch = c.given("--batch") ? c.batch : file.batch.value_or(c.batch);
  if (batch < 1 || batch > 1'000'000)  // the range the configuration file allows
    throw core::Error(core::ErrorKind::usage, "--batch must be in 1..1000000");
  const auto commit_interval = c.given("--commit-interval")
                                   ? core::parse_duration(c.commit_interval, 1'000'000)
                                   : file.commit_interval.value_or(core::parse_duration(c.commit_interval));
  s.store_options.durability =
      store::parse_durability(pick("--durability", c.durability, file.durability, "normal"));
  s.rt_priority = c.given("--rt-priority") ? c.rt_priority : file.rt_priority.value_or(0);
  s.cpu = c.given("--cpu") ? c.cpu : file.cpu.value_or(-1);
  s.irq_cpu = c.given("--irq-cpu") ? c.irq_cpu : file.irq_cpu.value_or(-1);
  s.mlock = c.mlock || file.mlock.value_or(false);

  // The source first: a wrong line or a missing permission should fail before the store is touched.
  nlohmann::json config{{"source", s.source_kind}, {"channels", nlohmann::json::array()}};
  if (s.source_kind == "gpio") {
    s.devices = capture::linux_gpio_devices();
    auto gpio = std::make_unique<capture::GpioSource>(
        *s.devices, s.channels, capture::GpioSourceOptions{s.node, "m2mlat-", c.event_buffer_size});
    for (const auto& w : gpio->warnings()) warn(w);
    s.consumers = gpio->consumers();
    s.source = std::move(gpio);
  } else if (s.source_kind == "kmsg") {
    s.source = std::make_unique<capture::KmsgSource>(
        capture::KmsgSourceOptions{s.node, pick("--kmsg", c.kmsg, file.kmsg, "/dev/kmsg"), s.channels});
  } else {
    capture::SimSourceOptions sim;
    sim.node = s.node;
    if (!s.channels.empty()) sim.channel = s.channels.front().name;
    sim.side = s.role == core::Role::cause ? core::Role::cause : core::Role::effect;
    sim.config = sim::preset(c.sim_preset);
    if (c.given("--seed")) sim.config.seed = c.sim_seed;
    sim::apply_overrides(sim.config, c.sim_set);
    sim.paced = c.sim_paced;
    config["sim_preset"] = c.sim_preset;
    config["sim_seed"] = sim.config.seed;
    if (!c.sim_set.empty()) config["sim_set"] = c.sim_set;
    s.source = std::make_unique<capture::SimSource>(std::move(sim));
  }

  if (!c.gyro.empty()) config["gyro"] = open_gyro(c, s);

  auto& options = s.options;
  options.session.node = s.node;
  options.session.role = s.role;
  options.session.label = pick("--label", c.label, file.label, "");
  options.session.scenario = pick("--scenario", c.scenario, file.scenario, store::kUnnamedScenario);
  for (const auto& spec : s.channels) {
    config["channels"].push_back(channel_json(spec));
    options.refractory[spec.name] = spec.refractory;
  }
  if (!c.config_path.empty()) config["config_file"] = c.config_path;
  options.session.config_json = config.dump();
  options.batch = static_cast<std::size_t>(batch);
  options.commit_interval = commit_interval;
  options.max_events = c.count;
  if (!c.duration.empty()) options.max_duration = core::parse_duration(c.duration);
  if (s.source_kind != "sim" && !c.no_clock_monitor && file.clock_monitor.value_or(true))
    start_clock_monitor(c, file, s);
  return s;
}

void add_record_options(CLI::App& sub, RecordFlags& flags) {
  auto* c = &flags;
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
  o["--seed"] =
      sub.add_option("--seed", c->sim_seed, "sim source: the simulated rig's seed (default the preset's)");
  o["--sim-set"] = sub.add_option("--sim-set", c->sim_set,
                                  "sim source: set one field of the simulated rig, KEY=VALUE (repeatable; "
                                  "see m2mlat simulate --list)");
  o["--no-clock-monitor"] =
      sub.add_flag("--no-clock-monitor", c->no_clock_monitor, "Do not store the clock's state (gpio, kmsg)");
  o["--kernel-interval"] = sub.add_option("--kernel-interval", c->kernel_interval,
                                          "Clock monitor: an adjtimex sample at least this often")
                               ->capture_default_str();
  o["--chrony-interval"] =
      sub.add_option("--chrony-interval", c->chrony_interval, "Clock monitor: read chronyc this often (0: never)")
          ->capture_default_str();
  o["--ptp-interval"] =
      sub.add_option("--ptp-interval", c->ptp_interval, "Clock monitor: read ptp4l's pmc this often (0: never)")
          ->capture_default_str();
  sub.add_option("--chronyc-socket", c->chronyc_socket, "Clock monitor: chronyd's command socket (chronyc -h)");
  sub.add_option("--pmc-socket", c->pmc_socket, "Clock monitor: ptp4l's Unix socket (pmc -s)");
  o["--gyro"] = sub.add_option("--gyro", c->gyro,
                               "A gyroscope channel: MPU-6050 at /dev/i2c-N[:ADDRESS] (default address 0x68), "
                               "or 'sim' (a simulated one: a rotation every 2 s)");
  sub.add_option("--gyro-channel", c->gyro_channel, "The gyroscope's channel name")->capture_default_str();
  sub.add_option("--gyro-keep", c->gyro_keep,
                 "Raw samples kept: all, or window:<ms> around each detected motion")
      ->capture_default_str();
  sub.add_option("--gyro-period", c->gyro_period, "The gyroscope's read period")->capture_default_str();
  sub.add_flag("--quiet", c->quiet, "No settings or live counters on stderr");
}

}  // namespace m2mlat::cli
