#include "m2mlat/analysis/import_follow.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <tuple>

#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"

namespace m2mlat::analysis {

namespace {

// Steps that are a board's own (not one it took over, which is no step of the other's to follow).
bool own(const store::ClockStep& s) { return s.origin != "followed" && s.origin != "follow_unchecked"; }

void add_unique(std::vector<store::ClockStep>& to, const store::ClockStep& step) {
  const auto same = [&](const store::ClockStep& s) {
    return std::tie(s.at_ns, s.earliest_ns, s.size_ns) == std::tie(step.at_ns, step.earliest_ns, step.size_ns);
  };
  if (own(step) && std::none_of(to.begin(), to.end(), same)) to.push_back(step);
}

std::vector<store::ClockStep> stored_steps(const store::Store& store, std::int64_t session_id) {
  std::vector<store::ClockStep> out;
  for (const auto& sample : store.clock_samples(session_id))
    if (auto step = store::clock_step_of(sample)) out.push_back(std::move(*step));
  return out;
}

// The file a session was imported from, if it was a kernel log.
std::optional<std::string> kernel_log_file(const store::Session& s) {
  const auto config = nlohmann::json::parse(s.config_json, nullptr, false);
  if (!config.is_object() || config.value("source", "") != "import" || config.value("format", "") != "kernel-log")
    return std::nullopt;
  for (const char* key : {"path", "file"})  // absolute since the follow is read; relative before
    if (config.contains(key) && config[key].is_string()) return config[key].get<std::string>();
  return std::nullopt;
}

// The earlier session's kernel log read again: its lines' two stamps, if the file still holds every
// event stored from it (a line filter of that import only left lines out); nullopt if not.
std::optional<ImportedLog> reread(const store::Store& store, const store::Session& s, const std::string& file) {
  // Never the store itself: a process must not open and close a file it holds SQLite connections to
  // (docs/store.md), and a store is no kernel log anyway.
  std::error_code error;
  if (std::filesystem::equivalent(file, store.path(), error) || error) return std::nullopt;
  formats::ImportedFile content;
  try {
    content = formats::import_file(file, formats::Format::kernel_log, {});
  } catch (const core::Error&) {
    return std::nullopt;
  }
  const auto* events = std::get_if<formats::EventImport>(&content.content);
  if (events == nullptr) return std::nullopt;
  ImportedLog log;
  std::vector<std::int64_t> lines;
  for (const auto& k : events->kernel_records) {
    lines.push_back(k.time_ns);
    if (!k.log_time_us) continue;
    log.realtime_ns.push_back(k.time_ns);
    log.log_time_us.push_back(*k.log_time_us);
  }
  if (log.realtime_ns.size() != lines.size()) log = {};  // lines without the log's stamp: nothing to read
  std::sort(lines.begin(), lines.end());
  store::EventFilter filter;
  filter.session_id = s.id;
  const auto end = s.end.value_or(core::TimePoint::from_ns(s.start.clock(), std::numeric_limits<std::int64_t>::max()));
  const auto stored = store.timestamps(s.start, end, filter);
  if (stored.t_ns.empty() || !std::includes(lines.begin(), lines.end(), stored.t_ns.begin(), stored.t_ns.end()))
    return std::nullopt;
  return log;
}

}  // namespace

ImportFollow follow_across_import(std::span<const ImportedLog> logs, const store::Store& store) {
  ImportFollow out;
  const auto sessions = store.sessions();
  std::vector<std::vector<store::ClockStep>> stored(sessions.size());
  for (std::size_t k = 0; k < sessions.size(); ++k) stored[k] = stored_steps(store, sessions[k].id);

  // Each log of this import against the steps the store holds for the scenario's other boards.
  for (const auto& log : logs) {
    std::vector<store::ClockStep> others;
    for (std::size_t k = 0; k < sessions.size(); ++k)
      if (sessions[k].node != log.node && sessions[k].scenario == log.scenario)
        for (const auto& s : stored[k]) add_unique(others, s);
    out.of_log.push_back(kernel_log_followed(others, log.steps, log.realtime_ns, log.log_time_us));
  }

  // Kernel logs imported earlier against this import's steps, from their files.
  for (std::size_t k = 0; k < sessions.size(); ++k) {
    const auto& s = sessions[k];
    const auto file = kernel_log_file(s);
    if (!file || !s.end) continue;
    std::vector<store::ClockStep> steps;
    for (const auto& log : logs)
      if (log.node != s.node && log.scenario == s.scenario)
        for (const auto& step : log.steps)
          if (step.earliest_ns <= s.end->ns() && step.at_ns >= s.start.ns()) add_unique(steps, step);
    if (steps.empty()) continue;
    if (const auto log = reread(store, s, *file)) {
      auto followed = kernel_log_followed(steps, stored[k], log->realtime_ns, log->log_time_us);
      if (!followed.empty()) out.earlier.push_back({s, std::move(followed), true});
      continue;
    }
    EarlierFollow unchecked{s, {}, false};
    for (const auto& step : steps) {
      store::ClockStep u;
      u.at_ns = step.at_ns;
      u.earliest_ns = step.earliest_ns;
      u.origin = "follow_unchecked";
      unchecked.steps.push_back(u);
    }
    out.notes.push_back(fmt::format(
        "{}: cannot be read again to see whether {} took over this import's clock step{} (the file no longer "
        "holds the events stored from it): {}'s events after {} are left out as after a step of unknown size; "
        "keep each board's kernel log in place until the other board's is imported",
        *file, s.node, steps.size() == 1 ? "" : "s", s.node, steps.size() == 1 ? "it" : "them"));
    out.earlier.push_back(std::move(unchecked));
  }
  return out;
}

}  // namespace m2mlat::analysis
