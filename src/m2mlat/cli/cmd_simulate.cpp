// `m2mlat simulate`: run the simulated rig and record it into a store (as two boards would) and/or
// write each node's events to a file, with the ground truth beside them.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <memory>
#include <span>

#include "m2mlat/analysis/clock_records.hpp"
#include "m2mlat/analysis/sim_markers.hpp"
#include "m2mlat/capture/sim_source.hpp"
#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/kernel_log_writer.hpp"
#include "m2mlat/formats/output_text.hpp"
#include "m2mlat/markers/markers_file.hpp"
#include "m2mlat/sim/generator.hpp"
#include "m2mlat/sim/overrides.hpp"
#include "m2mlat/sim/presets.hpp"
#include "m2mlat/sim/simulate.hpp"
#include "m2mlat/sim/stage_markers.hpp"

namespace m2mlat::cli {

namespace {

struct SimulateCommand {
  std::string preset = "static_wifi";
  std::uint64_t seed = 0;  // 0: the preset's own seed
  std::int64_t manoeuvres = 0;
  std::vector<std::string> overrides;
  std::string store_path;
  std::string out_dir;
  std::string format = "events-csv";
  std::uint32_t pin = 16;
  std::string label = "sim";
  std::string board = "both";  // the full loop: which board's store this is
  bool list = false;
  bool markers = false;       // also markers.csv and stages.txt (sim/stage_markers.hpp)
  double markers_drop = 0;    // each marker left out with this chance
};

// The run's stage markers (the command of each pass, from the operator's wheel to the vehicle's) as
// m2mlat-markers/1, and the stage rule that cuts the events with them (docs/breakdown.md).
void write_stage_markers(const sim::RigConfig& config, const std::string& dir, double drop) {
  const auto run = sim::simulate(config);
  const auto stages = sim::stage_markers(run, {drop});
  const auto markers = analysis::to_markers(stages, run.config);
  core::write_output_file((std::filesystem::path(dir) / "markers.csv").string(), markers::markers_csv(markers));
  core::write_output_file(
      (std::filesystem::path(dir) / "stages.txt").string(),
      "# The simulated rig's stages (docs/breakdown.md): NAME = the marker that ends it\n" +
          sim::stage_rule_text(config.cause_node, config.effect_node));
  fmt::print("{}: markers.csv ({} markers of {} commands, {} dropped), stages.txt\n", core::printable(dir),
             markers.size(), stages.chains.size(), stages.dropped);
}

// A run into a scenario the store holds already would overlap it in time (the simulator's runs start
// at the configuration's start): its copies would pair as bounces. Refused, naming what is there.
void refuse_recorded(const store::Store& store, const std::string& scenario, std::span<const std::string> nodes) {
  for (const auto& s : store.sessions())
    if (s.scenario == scenario && std::find(nodes.begin(), nodes.end(), s.node) != nodes.end())
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: scenario '{}' already has a session of {} (session {}): record the run "
                                    "under another scenario name (--set scenario=NAME) or into another store",
                                    store.path(), scenario, s.node, s.id));
}

// The full-loop presets (sim/full_loop.hpp): the run recorded as the boards would record it, into a
// store per board (--board station|vehicle, the same --seed for both) or both in one.
int full_loop_into_store(const SimulateCommand& c, sim::FullLoopConfig config) {
  if (c.store_path.empty() || !c.out_dir.empty() || !c.overrides.empty())
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("{} is recorded into a store: give --store, and no --out-dir or --set", c.preset));
  if (c.seed != 0) config.seed = c.seed;
  if (c.manoeuvres > 0) config.manoeuvres = static_cast<int>(std::min<std::int64_t>(c.manoeuvres, 100'000));
  sim::check(config);
  const auto boards = c.board == "station"   ? capture::FullLoopBoards::station
                      : c.board == "vehicle" ? capture::FullLoopBoards::vehicle
                                             : capture::FullLoopBoards::both;
  if (config.single_board)  // refused before a store file is made
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("{} has no gyroscopes: run it with `demo --scenario {}`", c.preset, c.preset));
  const auto run = sim::simulate_full_loop(config);
  auto store = store::Store::open(c.store_path);
  std::vector<std::string> nodes;
  if (boards != capture::FullLoopBoards::vehicle) nodes.emplace_back("station");
  if (boards != capture::FullLoopBoards::station) nodes.emplace_back("vehicle");
  refuse_recorded(store, c.preset, nodes);
  const auto rec = capture::record_full_loop(store, run, boards, c.label, c.preset);
  fmt::print(
      "{}: scenario {} recorded: {} manoeuvres, sessions station {}, vehicle {}, led {} (0: not here)\n",
      core::printable(c.store_path), core::printable(c.preset), run.manoeuvres.size(), rec.station_session,
      rec.vehicle_session, rec.led_session);
  return 0;
}

// The true pairs: which cause and effect events (0-based index in each node's file) belong together.
void write_truth(std::ostream& out, const std::vector<sim::TruePair>& pairs) {
  formats::OutputBuffer buffer(out);
  buffer << "pass,cause_index,effect_index,true_latency_ns,measured_latency_ns\n";
  for (const auto& p : pairs) {
    buffer.integer(p.pass) << ',';
    buffer.integer(p.cause_index) << ',';
    buffer.integer(p.effect_index) << ',';
    buffer.integer(p.true_latency.count()) << ',';
    buffer.integer(p.measured_latency.count()) << '\n';
    buffer.end_record();
  }
  buffer.flush();
}

void list_presets() {
  for (const auto& p : sim::presets()) fmt::print("{:<24} {}\n", p.name, p.description);
  fmt::print("\nsettable with --set key=value:\n");
  for (const auto& f : sim::settable_fields()) fmt::print("  {:<40} {}\n", f.key, f.help);
}

// The node names become file names in the folder: one that is not a plain name would write
// elsewhere ("../x.csv" beside the folder, "/etc/x" anywhere).
void check_file_name(const std::string& key, const std::string& node) {
  if (node.empty() || node == "." || node == ".." || node.find('/') != std::string::npos ||
      node.find('\0') != std::string::npos)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{} '{}': with --out-dir the node name is a file name: it cannot be empty, "
                                  "'.', '..' or hold a '/'",
                                  key, node));
}

// The node's clock samples and steps as the events files carry them.
std::vector<formats::ClockRecord> clock_records(const sim::Simulation& run, const sim::RigConfig& config,
                                                core::Role role, const std::string& node) {
  std::vector<formats::ClockRecord> out;
  const auto reference = capture::sim_reference(config, role);
  for (const auto& s : run.clock_samples)
    if (s.node == role)
      out.push_back(analysis::to_clock_record(capture::sim_clock_sample(s, 0, reference), node));
  return out;
}

// The kernel log's own stamp of each event (us since boot, CLOCK_MONOTONIC): the true time of the
// kernel's timestamp plus a printk delay of 20..200 us, the board booted 1000 s before the run.
// CLOCK_MONOTONIC is never stepped, so a clock step shows in realtime - monotonic.
std::vector<std::int64_t> log_times_us(const std::vector<sim::EventTruth>& truth, std::int64_t boot_ns,
                                       std::int64_t first_index) {
  std::vector<std::int64_t> out;
  out.reserve(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const auto index = static_cast<std::uint64_t>(first_index) + i;
    const std::int64_t delay_ns = 20'000 + static_cast<std::int64_t>((index * 2654435761u) % 180'000u);
    out.push_back((truth[i].true_time.ns() + truth[i].irq_latency.count() + delay_ns - boot_ns) / 1000);
  }
  return out;
}

// Files: kernel-log streams chunk by chunk (any length); the event formats are written whole.
void write_files(const sim::RigConfig& config, const std::string& dir, formats::Format format,
                 std::uint32_t pin) {
  check_file_name("cause_node", config.cause_node);
  check_file_name("effect_node", config.effect_node);
  std::filesystem::create_directories(dir);
  const auto name = [&](const std::string& node, const char* ext) {
    return (std::filesystem::path(dir) / (node + ext)).string();
  };
  std::vector<sim::TruePair> truth;
  if (format == formats::Format::kernel_log) {
    // The reference rig's log has one kind of edge, and no field that says which.
    if (config.cause_sensor.both_edges || config.effect_sensor.both_edges)
      throw core::Error(
          core::ErrorKind::usage,
          "a kernel log holds one kind of edge: both_edges needs --format events-csv or events-jsonl");
    // Both logs are written at once, chunk by chunk: the effect's file inside the cause's.
    core::write_output_file(name(config.cause_node, ".log"), [&](std::ostream& cause) {
      core::write_output_file(name(config.effect_node, ".log"), [&](std::ostream& effect) {
        formats::KernelLogWriter cause_log(cause, pin), effect_log(effect, pin);
        sim::Generator generator(config);
        sim::Chunk chunk;
        std::int64_t total = 0;
        while (generator.next(chunk, 1 << 18)) {
          const std::int64_t boot_ns = config.start.ns() - 1'000'000'000'000;
          cause_log.write(chunk.cause_events, log_times_us(chunk.cause_truth, boot_ns, chunk.cause_first_index));
          effect_log.write(chunk.effect_events,
                           log_times_us(chunk.effect_truth, boot_ns, chunk.effect_first_index));
          truth.insert(truth.end(), chunk.pairs.begin(), chunk.pairs.end());
          total += static_cast<std::int64_t>(chunk.event_count());
          progress(fmt::format("simulating: {} events", total));
        }
        progress_done();
      });
    });
  } else {
    const auto run = sim::simulate(config);
    const char* ext = format == formats::Format::events_jsonl ? ".jsonl" : ".csv";
    // The boards' files are inputs for `import`: they keep their clock records (with_meta).
    const auto cause_clocks = clock_records(run, config, core::Role::cause, config.cause_node);
    const auto effect_clocks = clock_records(run, config, core::Role::effect, config.effect_node);
    formats::EventExportOptions cause_options{.clocks = cause_clocks, .origins = {}, .with_meta = true};
    formats::EventExportOptions effect_options{.clocks = effect_clocks, .origins = {}, .with_meta = true};
    formats::export_events(name(config.cause_node, ext), format, run.cause_events, cause_options);
    formats::export_events(name(config.effect_node, ext), format, run.effect_events, effect_options);
    truth = run.pairs;
  }
  core::write_output_file(name("truth", ".csv"), [&](std::ostream& out) { write_truth(out, truth); });
}

int run_simulate(const SimulateCommand& c) {
  if (c.list) {
    list_presets();
    return 0;
  }
  if (c.store_path.empty() && c.out_dir.empty())
    throw core::Error(core::ErrorKind::usage, "say where the run goes: --store FILE and/or --out-dir DIR");
  if (c.out_dir.empty() && (c.markers || c.markers_drop != 0))
    throw core::Error(core::ErrorKind::usage, "--markers writes markers.csv into --out-dir DIR: give it");
  if (!(c.markers_drop >= 0 && c.markers_drop <= 1))
    throw core::Error(core::ErrorKind::usage, fmt::format("--markers-drop {} is not in [0, 1]", c.markers_drop));
  if (auto loop = sim::full_loop_preset(c.preset)) return full_loop_into_store(c, *loop);
  auto config = sim::preset(c.preset);
  if (c.seed != 0) config.seed = c.seed;
  if (c.manoeuvres > 0) config.manoeuvres = c.manoeuvres;
  sim::apply_overrides(config, c.overrides);
  const auto format = formats::parse_format(c.format);
  if (format != formats::Format::kernel_log && format != formats::Format::events_csv &&
      format != formats::Format::events_jsonl)
    throw core::Error(core::ErrorKind::usage, "--format: kernel-log, events-csv or events-jsonl");

  if (!c.store_path.empty()) {
    // Ctrl-C (or SIGTERM) ends the run with nothing of it stored; a store this run made goes with it.
    capture::StopSignal stop;
    const bool existed = std::filesystem::exists(c.store_path);
    capture::RecordedRun run;
    try {
      auto store = store::Store::open(c.store_path);
      refuse_recorded(store, config.scenario, std::array{config.cause_node, config.effect_node});
      run = capture::record_simulation(store, config, c.label, [&](const sim::Chunk&, std::int64_t events) {
        progress(fmt::format("recording: {} events", events));
        if (const auto signal = stop.take(); !signal.empty())
          throw core::Error(core::ErrorKind::interrupted,
                            fmt::format("{}: {} before the run was recorded: nothing of it stored", c.store_path, signal));
      });
    } catch (const core::Error&) {
      progress_done();
      if (!existed) store::remove_store_files(c.store_path);
      throw;
    }
    progress_done();
    fmt::print("{}: scenario {} recorded: {} events on {} (session {}), {} on {} (session {})\n",
               core::printable(c.store_path), core::printable(config.scenario), run.cause_events,
               core::printable(config.cause_node), run.cause_session, run.effect_events,
               core::printable(config.effect_node), run.effect_session);
  }
  if (!c.out_dir.empty()) {
    write_files(config, c.out_dir, format, c.pin);
    fmt::print("{}: {} and {} events ({}), truth.csv\n", core::printable(c.out_dir),
               core::printable(config.cause_node), core::printable(config.effect_node), c.format);
    if (c.markers) write_stage_markers(config, c.out_dir, c.markers_drop);
  }
  return 0;
}

}  // namespace

Runner attach_simulate(CLI::App& sub) {
  auto c = std::make_shared<SimulateCommand>();
  sub.add_option("--scenario", c->preset, "Preset to start from (--list shows them)")->capture_default_str();
  sub.add_option("--seed", c->seed, "Seed: the same seed gives the same run (default: the preset's)");
  sub.add_option("--manoeuvres", c->manoeuvres, "Number of manoeuvres (default: the preset's)");
  sub.add_option("--set", c->overrides, "Override a field, key=value (repeatable; --list shows the keys)");
  sub.add_option("--store", c->store_path, "Record into this store (created if missing)");
  sub.add_option("--out-dir", c->out_dir, "Write <node>.<ext> per node and truth.csv into this folder");
  sub.add_option("--format", c->format, "File format: events-csv, events-jsonl or kernel-log")
      ->capture_default_str();
  sub.add_option("--pin", c->pin, "GPIO pin number written in kernel-log lines")->capture_default_str();
  sub.add_option("--label", c->label, "Session label in the store")->capture_default_str();
  sub.add_option("--board", c->board, "full_loop, full_loop_baseline: the board(s) this store records")
      ->check(CLI::IsMember({"station", "vehicle", "both"}))
      ->capture_default_str();
  sub.add_flag("--markers", c->markers,
               "With --out-dir: also markers.csv (each command's way, operator to vehicle) and stages.txt "
               "(the stage rule for stats --markers --stages)");
  sub.add_option("--markers-drop", c->markers_drop, "Leave each marker out with this chance (incomplete chains)");
  sub.add_flag("--list", c->list, "List the presets and the settable fields");
  return [c] { return run_simulate(*c); };
}

}  // namespace m2mlat::cli
