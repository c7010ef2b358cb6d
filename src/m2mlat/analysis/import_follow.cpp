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

// A board's own step, not one it took over from the other (which is no step of the other's to follow).
bool own(const store::ClockStep& s) { return s.origin != "followed" && s.origin != "follow_unchecked"; }

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

// The session's kernel log read again: its lines' two stamps, if the file still holds every event
// stored from it (a line filter of that import only left lines out); nullopt if not.
std::optional<LogStamps> reread(const store::Store& store, const store::Session& s, const std::string& file) {
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
  std::vector<std::int64_t> lines;
  for (const auto& k : events->kernel_records) lines.push_back(k.time_ns);
  std::sort(lines.begin(), lines.end());
  store::EventFilter filter;
  filter.session_id = s.id;
  const auto end = s.end.value_or(core::TimePoint::from_ns(s.start.clock(), std::numeric_limits<std::int64_t>::max()));
  const auto stored = store.timestamps(s.start, end, filter);
  if (stored.t_ns.empty() || !std::includes(lines.begin(), lines.end(), stored.t_ns.begin(), stored.t_ns.end()))
    return std::nullopt;
  return log_stamps(events->kernel_records);
}

}  // namespace

StoreFollow follow_in_store(const store::Store& store, const std::set<std::string>& scenarios,
                            const std::map<std::int64_t, LogStamps>& in_memory) {
  StoreFollow out;
  const auto sessions = store.sessions();
  std::vector<std::vector<store::ClockStep>> steps(sessions.size());
  for (std::size_t k = 0; k < sessions.size(); ++k)
    if (scenarios.contains(sessions[k].scenario)) steps[k] = stored_steps(store, sessions[k].id);

  for (std::size_t k = 0; k < sessions.size(); ++k) {
    const auto& s = sessions[k];
    const auto file = kernel_log_file(s);
    if (!scenarios.contains(s.scenario) || !file || !s.end) continue;
    // The other boards' own steps within this log's time that its board has not yet taken over (or
    // been left out after), and the steps of its own (a step of its own is no follow).
    std::vector<store::ClockStep> others, taken, mine;
    for (std::size_t j = 0; j < sessions.size(); ++j) {
      if (sessions[j].scenario != s.scenario) continue;
      for (const auto& step : steps[j]) {
        if (sessions[j].node == s.node) (own(step) ? mine : taken).push_back(step);
        else if (own(step) && step.earliest_ns <= s.end->ns() && step.at_ns >= s.start.ns()) others.push_back(step);
      }
    }
    std::erase_if(others, [&](const store::ClockStep& step) {
      return std::any_of(taken.begin(), taken.end(), [&](const auto& t) { return t.earliest_ns == step.earliest_ns; });
    });
    // One board's log imported twice holds its steps twice: each is followed once.
    const auto key = [](const store::ClockStep& c) { return std::tie(c.earliest_ns, c.at_ns, c.size_ns); };
    std::sort(others.begin(), others.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    others.erase(std::unique(others.begin(), others.end(), [&](const auto& a, const auto& b) { return key(a) == key(b); }),
                 others.end());
    if (others.empty()) continue;

    std::optional<LogStamps> stamps;
    if (const auto it = in_memory.find(s.id); it != in_memory.end()) stamps = it->second;
    else stamps = reread(store, s, *file);
    if (stamps) {
      auto followed = kernel_log_followed(others, mine, stamps->realtime_ns, stamps->log_time_us);
      if (!followed.empty()) out.followed.push_back({s, std::move(followed), true});
      continue;
    }
    FollowedSteps unchecked{s, {}, false};
    for (const auto& step : others) {
      store::ClockStep u;
      u.at_ns = step.at_ns;
      u.earliest_ns = step.earliest_ns;
      u.origin = "follow_unchecked";
      unchecked.steps.push_back(u);
    }
    out.notes.push_back(fmt::format(
        "{}: cannot be read again to see whether {} took over {} clock step{} of another board (the file no "
        "longer holds the events stored from it): {}'s events after {} are left out as after a step of unknown "
        "size; keep each board's kernel log in place until the other board's is imported",
        *file, s.node, others.size(), others.size() == 1 ? "" : "s", s.node, others.size() == 1 ? "it" : "them"));
    out.followed.push_back(std::move(unchecked));
  }
  return out;
}

StoreFollow take_over_steps(store::Store& store, const std::set<std::string>& scenarios,
                            const std::map<std::int64_t, LogStamps>& in_memory, const std::string& source,
                            const std::string& label) {
  auto follow = follow_in_store(store, scenarios, in_memory);
  for (const auto& f : follow.followed) {
    store::Session session;
    session.node = f.follower.node;
    session.role = f.follower.role;
    session.label = label.empty() ? f.follower.label : label;
    session.scenario = f.follower.scenario;
    session.config_json =
        nlohmann::json{{"source", source}, {"followed_from", f.follower.id}, {"checked", f.checked}}.dump();
    session.start = core::TimePoint::from_ns(f.follower.start.clock(), f.steps.front().earliest_ns);
    const auto id = store.begin_session(session);
    std::vector<store::ClockSample> samples;
    for (const auto& step : f.steps) {
      samples.push_back(store::step_clock_sample(step));
      samples.back().session_id = id;
    }
    store.append_clock_samples(samples);
    store.end_session(id, session.start);
  }
  return follow;
}

nlohmann::json to_json(const FollowedSteps& f) {
  return {{"node", f.follower.node},
          {"scenario", f.follower.scenario},
          {"steps", f.steps.size()},
          {"checked", f.checked},
          {"follower_session", f.follower.id}};
}

std::string followed_line(const FollowedSteps& f) {
  return fmt::format("{}: {} clock step{} of another board taken over ({}) -> scenario '{}'", f.follower.node,
                     f.steps.size(), f.steps.size() == 1 ? "" : "s",
                     f.checked ? "seen in its kernel log" : "its kernel log gone: size unknown", f.follower.scenario);
}

}  // namespace m2mlat::analysis
