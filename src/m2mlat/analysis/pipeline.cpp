// The offline pipeline: resolving stores and data files into analysed scenarios.
#include "m2mlat/analysis/pipeline.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <future>
#include <set>
#include <tuple>
#include <utility>

#include "m2mlat/analysis/board_record.hpp"
#include "m2mlat/analysis/clock_records.hpp"
#include "m2mlat/analysis/clock_steps.hpp"
#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/analysis/pairs_file.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

namespace {

// A board's kernel log: its two stamps per line and the steps they show, kept until the other
// board's steps are known (kernel_log_followed).
struct LogClock {
  LogStamps stamps;
  std::vector<store::ClockStep> steps;
};

// The clock state a data file carries: its clock records (m2mlat's events files) and the steps its
// kernel-log lines show (kernel_log_steps.hpp), the latter on `node` (the node its events are on);
// returns the kernel log's stamps (empty without).
LogClock add_file_clock(BoardRecord& record, const formats::ImportedFile& file, const std::string& node) {
  LogClock log;
  const auto* events = std::get_if<formats::EventImport>(&file.content);
  if (events == nullptr) return log;
  for (const auto& r : events->clock_records) record.add(r.node, to_clock_sample(r));
  log.stamps = log_stamps(events->kernel_records);
  if (log.stamps.realtime_ns.empty()) return log;
  const auto clock = kernel_log_clock(log.stamps.realtime_ns, log.stamps.log_time_us);
  for (const auto& step : clock.steps) record.samples[node].push_back(store::step_clock_sample(step));
  for (auto& lines : unknown_clock_runs(log.stamps.realtime_ns, clock.left_out)) record.unknown_clock[node].push_back(std::move(lines));
  if (clock.limits.any()) record.log_limits[node] = clock.limits;
  log.steps = clock.steps;
  return log;
}

// Each board's kernel log against the other board's steps: a board that took the other's step over
// (a co-referenced rig's follower, kernel_log_followed) gets it as a step of its own.
void add_followed(BoardRecord& record, const std::string& cause_node, const LogClock& cause,
                  const std::string& effect_node, const LogClock& effect) {
  for (const auto& f :
       kernel_log_followed(effect.steps, cause.steps, cause.stamps.realtime_ns, cause.stamps.log_time_us))
    record.samples[cause_node].push_back(store::step_clock_sample(f));
  for (const auto& f :
       kernel_log_followed(cause.steps, effect.steps, effect.stamps.realtime_ns, effect.stamps.log_time_us))
    record.samples[effect_node].push_back(store::step_clock_sample(f));
}

// Pairs and summarises `input` after its boards' clock steps (clock_steps.hpp), then attaches what
// `record` holds (clock series, losses, per-sample uncertainty) when it holds anything.
ScenarioResult analyse_with_record(ScenarioInput input, const BoardRecord& record, const PipelineOptions& options) {
  leave_out_unknown_clock(input, record.unknown_clock);
  auto steps = correct_scenario(input, record.of(input.cause_ref.node), record.of(input.effect_ref.node));
  for (auto [side, node] : {std::pair{&steps.cause, &input.cause_ref.node}, std::pair{&steps.effect, &input.effect_ref.node}})
    if (const auto it = record.log_limits.find(*node); it != record.log_limits.end()) side->limits = it->second;
  auto result = analyse(std::move(input), std::move(steps), options.match, options.summary, options.include_ambiguous);
  if (!record.samples.empty() || !record.losses.empty())
    attach_board_record(result, record, options.uncertainty, options.summary);
  return result;
}

std::vector<core::Event> events_of(formats::ImportedFile&& file, const std::string& path) {
  if (auto* events = std::get_if<formats::EventImport>(&file.content)) return std::move(events->events);
  if (auto* paired = std::get_if<formats::PairedImport>(&file.content)) {
    auto all = std::move(paired->causes);
    all.insert(all.end(), paired->effects.begin(), paired->effects.end());
    return all;
  }
  if (std::holds_alternative<formats::SyncImport>(file.content))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: a synchronisation-test file holds offsets, not edge events", path));
  throw core::Error(core::ErrorKind::data,
                    fmt::format("{}: a {} file holds the full-loop rig's results, not edge events to pair: "
                                "summarise it with `m2mlat stats` or `m2mlat report`",
                                path, formats::to_string(file.format)));
}

// A paired-results CSV analysed with its own rows as the pairs (what the rig itself reported).
ScenarioResult as_given(std::string scenario, const formats::PairedImport& paired,
                        const stats::SummaryOptions& options) {
  ScenarioResult r;
  r.input.scenario = std::move(scenario);
  r.input.id_kind = "line";
  if (!paired.causes.empty()) r.input.cause_ref = {paired.causes.front().node, paired.causes.front().channel};
  if (!paired.effects.empty())
    r.input.effect_ref = {paired.effects.front().node, paired.effects.front().channel};
  for (std::size_t i = 0; i < paired.pairs.size(); ++i) {
    const auto line = static_cast<std::int64_t>(paired.checks.at(i).line);
    r.input.cause.seq.push_back(line);
    r.input.cause.t_ns.push_back(paired.pairs[i].cause_time.ns());
    r.input.effect.seq.push_back(line);
    r.input.effect.t_ns.push_back(paired.pairs[i].effect_time.ns());
  }
  r.match.pairs = pairs_from_rows(paired.pairs);
  r.match.cause_count = r.match.effect_count = static_cast<std::int64_t>(paired.pairs.size());
  summarize(r, options);
  return r;
}

// The reference rig's kernel log and export CSV hold one pin per line and nothing but timestamps:
// read only those (8 bytes an edge, no events built; 16 with the log's own stamps) when the file has
// one pin and no other channel was asked for. nullopt: take the general path.
struct LeanSide {
  SideInput side;
  std::vector<store::ClockSample> steps;  // the kernel log's clock steps (kernel_log_steps.hpp)
  std::vector<store::UnknownClock> unknown;  // its lines on no known clock
  LogClockLimits limits;  // the steps the log cannot show
  LogClock log;  // the log's printk stamps and its steps (its realtime stamps are side.t_ns)
};
std::optional<LeanSide> lean_side(const std::string& path, std::optional<formats::Format> format,
                                  const std::string& node, const std::optional<core::ChannelRef>& want) {
  // A raw read of a data file: safe here, before this process opens any store (see docs/store.md
  // on why a process must never open and close a store file it holds SQLite connections to).
  if (!format) format = formats::detect_file_format(path);
  if (format != formats::Format::kernel_log && format != formats::Format::rig_export_csv) return std::nullopt;
  auto series = formats::read_timestamps(path, format);
  if (series.size() != 1) return std::nullopt;
  auto& only = series.front();
  const bool numeric = !only.label.empty() && only.label.find_first_not_of("0123456789") == std::string::npos;
  LeanSide lean;
  const auto clock = kernel_log_clock(only.ns, only.log_time_us);
  for (const auto& step : clock.steps) lean.steps.push_back(store::step_clock_sample(step));
  lean.unknown = unknown_clock_runs(only.ns, clock.left_out);
  lean.limits = clock.limits;
  lean.log.steps = clock.steps;
  lean.log.stamps.log_time_us = std::move(only.log_time_us);
  lean.side = SideInput{{node, numeric ? "gpio" + only.label : only.label}, std::move(only.ns)};
  if (want && (want->node != lean.side.ref.node ||
               (!want->channel.empty() && want->channel != lean.side.ref.channel)))
    return std::nullopt;
  return lean;
}

// Names for the scenario of --cause-file and --effect-file. A file that names no board (a kernel
// log) is the board of its file name (operator.log: "operator"), unless both files have the same name
// ("cause" and "effect" then); the scenario is the one --scenario names, else the folder both files
// are in, else "<cause>-<effect>".
struct FilePairNames {
  std::string cause, effect, scenario;
};
FilePairNames file_pair_names(const PipelineInputs& inputs) {
  const std::filesystem::path cause(inputs.cause_file), effect(inputs.effect_file);
  FilePairNames names{cause.stem().string(), effect.stem().string(), {}};
  if (names.cause.empty() || names.effect.empty() || names.cause == names.effect) names.cause = "cause", names.effect = "effect";
  const auto folder = [](const std::filesystem::path& p) {
    return std::filesystem::absolute(p).lexically_normal().parent_path();
  };
  if (inputs.scenarios.size() == 1)
    names.scenario = inputs.scenarios.front();
  else if (folder(cause) == folder(effect) && cause.has_parent_path() && effect.has_parent_path())
    names.scenario = folder(cause).filename().string();
  if (names.scenario.empty()) names.scenario = names.cause + "-" + names.effect;
  return names;
}

}  // namespace

ScenarioResult analyse_store_scenario(const store::Store& store, const std::string& scenario,
                                      const PipelineOptions& options) {
  auto input = load_scenario(store, scenario, options.selection);
  const auto record = read_board_record(store, input);
  return analyse_with_record(std::move(input), record, options);
}

std::vector<ScenarioResult> analyse_inputs(const PipelineInputs& inputs, const PipelineOptions& options) {
  const auto& selection = options.selection;
  const auto& summary_options = options.summary;
  const auto format = inputs.format;
  formats::ImportOptions import_options;

  if (inputs.inputs.empty() && inputs.cause_file.empty())
    throw core::Error(core::ErrorKind::usage,
                      "no input: give a store or data files, or --cause-file and --effect-file");
  if (inputs.cause_file.empty() != inputs.effect_file.empty())
    throw core::Error(core::ErrorKind::usage, "--cause-file and --effect-file go together");

  std::vector<ScenarioResult> results;
  if (!inputs.cause_file.empty()) {
    // The two files are read side by side (reading is a quarter of `stats` on two large logs); an
    // error in the cause file is still the one reported when both have one.
    const auto names = file_pair_names(inputs);
    const auto& scenario = names.scenario;
    // The interference filter (--min-pulse) needs each edge's kind, which the bare read has not: the
    // events' path below then, which names a file that holds one kind only (and no thread is started).
    const bool read_bare = selection.min_pulse.count() == 0;
    auto effect_read =
        std::async(read_bare ? std::launch::async : std::launch::deferred, [&]() -> std::optional<LeanSide> {
          if (!read_bare) return std::nullopt;
          return lean_side(inputs.effect_file, format, names.effect, selection.effect);
        });
    auto cause =
        read_bare ? lean_side(inputs.cause_file, format, names.cause, selection.cause) : std::nullopt;
    auto effect = effect_read.get();
    BoardRecord record;
    if (cause && effect) {
      record.samples[names.cause] = std::move(cause->steps);
      record.samples[names.effect] = std::move(effect->steps);
      if (!cause->unknown.empty()) record.unknown_clock[names.cause] = std::move(cause->unknown);
      if (!effect->unknown.empty()) record.unknown_clock[names.effect] = std::move(effect->unknown);
      // The logs' realtime stamps are the sides' own: lent and moved back (no copy of 10^7 stamps),
      // and the printk stamps freed before the pairing.
      cause->log.stamps.realtime_ns = std::move(cause->side.t_ns);
      effect->log.stamps.realtime_ns = std::move(effect->side.t_ns);
      add_followed(record, names.cause, cause->log, names.effect, effect->log);
      cause->side.t_ns = std::move(cause->log.stamps.realtime_ns);
      effect->side.t_ns = std::move(effect->log.stamps.realtime_ns);
      cause->log = {};
      effect->log = {};
      if (record.samples[names.cause].empty() && record.samples[names.effect].empty()) record.samples.clear();
      for (const auto& [node, lean] : {std::pair{&names.cause, &*cause}, std::pair{&names.effect, &*effect}})
        if (lean->limits.any()) record.log_limits[*node] = lean->limits;
      results.push_back(analyse_with_record(
          from_timestamps(scenario, std::move(cause->side), std::move(effect->side)), record, options));
    } else {
      import_options.node = names.cause;
      auto cause_file = formats::import_file(inputs.cause_file, format, import_options);
      auto cause_log = add_file_clock(record, cause_file, import_options.node);
      const auto causes = events_of(std::move(cause_file), inputs.cause_file);
      import_options.node = names.effect;
      auto effect_file = formats::import_file(inputs.effect_file, format, import_options);
      auto effect_log = add_file_clock(record, effect_file, import_options.node);
      const auto effects = events_of(std::move(effect_file), inputs.effect_file);
      add_followed(record, names.cause, cause_log, names.effect, effect_log);
      cause_log = {};
      effect_log = {};
      results.push_back(analyse_with_record(
          from_events(scenario, causes, effects, selection, {inputs.cause_file, inputs.effect_file, {}}), record,
          options));
    }
  }
  for (const auto& path : inputs.inputs) {
    if (!std::filesystem::exists(path) && path != "-")
      throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such file", path));
    if (store::is_sqlite_database(path)) {
      store::Options read;
      read.read_only = true;
      const auto store = store::Store::open(path, read);
      auto names = inputs.scenarios.empty() ? scenarios(store) : inputs.scenarios;
      // Events recorded outside any run (an agent's first session, before a coordinator began one;
      // an agent given no scenario) are no scenario of their own beside the runs: said, not analysed.
      const auto outside = std::find(names.begin(), names.end(), store::kUnnamedScenario);
      std::int64_t outside_events = 0;
      if (inputs.scenarios.empty() && names.size() > 1 && outside != names.end()) {
        names.erase(outside);
        for (const auto& session : store.sessions())
          if (session.scenario == store::kUnnamedScenario) outside_events += store.event_count(session.id);
      }
      const auto first = results.size();
      for (const auto& name : names)
        if (std::find(inputs.skip.begin(), inputs.skip.end(), std::pair{path, name}) == inputs.skip.end())
          results.push_back(analyse_store_scenario(store, name, options));
      if (outside_events != 0 && results.size() > first)
        results[first].warnings.push_back(
            {"outside_runs", fmt::format("{}: {} events were recorded outside any run (before a session began, or by "
                                         "an agent given no --scenario; stored as scenario '{}'): they are in "
                                         "none of these figures (--scenario {} analyses them)",
                                         path, outside_events, store::kUnnamedScenario, store::kUnnamedScenario)});
      continue;
    }
    const auto scenario = std::filesystem::path(path).stem().string();
    // Not a store (checked through SQLite), and no store of this loop is open any more: a raw read
    // of the file cannot drop a lock of a connection of this process.
    auto file = formats::import_file(path, format, import_options);
    if (const auto* paired = std::get_if<formats::PairedImport>(&file.content); paired && !inputs.rematch) {
      results.push_back(as_given(scenario, *paired, summary_options));
      continue;
    }
    // An events file with both sides: split by the selection (or by the conventional node names).
    auto sel = selection;
    if (!sel.cause) sel.cause = core::ChannelRef{"operator", ""};
    if (!sel.effect) sel.effect = core::ChannelRef{"vehicle", ""};
    BoardRecord record;
    add_file_clock(record, file, import_options.node);
    const auto events = events_of(std::move(file), path);
    constexpr std::string_view advice =
        ": a data file is one scenario with both boards' edges; pair one file per board with --cause-file and "
        "--effect-file, or name the nodes with --cause and --effect";
    results.push_back(analyse_with_record(from_events(scenario, events, events, sel, {path, path, advice}), record,
                                          options));
  }
  return results;
}

}  // namespace m2mlat::analysis
