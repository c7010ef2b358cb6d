// A board that followed the other's clock step, seen in a store built from kernel logs.
// kernel_log_followed reads a board's own printk stamps against the other board's steps; the store
// keeps no printk stamps, and `import` reads one board's log at a time. So after an import or a
// merge, each kernel-log session of the scenarios it touched is read against the steps the store
// holds for the scenario's other boards: from the stamps in memory (the log just imported), or
// from its file again (the session's configuration names it; the file must still hold every event
// stored from it). A file gone or changed cannot show whether its board followed: its stamps from
// each such step on are left out as after a step of unknown size (origin "follow_unchecked"), and a
// note says so. A step a board has taken over (or left out) once is not looked at again.
// Without it a store built from a co-referenced rig's kernel logs corrected the stepped board's
// events and not the follower's: every later latency off by the step.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

// Steps a board took over: to be stored as a session of their own (no events) beside `follower`.
struct FollowedSteps {
  store::Session follower;  // the stored kernel-log session whose board took them over
  std::vector<store::ClockStep> steps;
  bool checked = true;  // false: its file could not be read again, the steps are of unknown size
};

struct StoreFollow {
  std::vector<FollowedSteps> followed;
  std::vector<std::string> notes;  // for stderr: a file that could not be read again
};

// The kernel-log sessions of `scenarios` in `store` (only read) against the other boards' steps;
// `in_memory`: stamps already read, by session id (the others are read from their files).
StoreFollow follow_in_store(const store::Store& store, const std::set<std::string>& scenarios,
                            const std::map<std::int64_t, LogStamps>& in_memory = {});

// follow_in_store, and what it found stored: each FollowedSteps as a session of its own (no events,
// configuration {"source": <source>, "followed_from": <follower id>, "checked": ...}, at its first
// step; labelled `label`, or the follower's label when empty). Returns what it found.
StoreFollow take_over_steps(store::Store& store, const std::set<std::string>& scenarios,
                            const std::map<std::int64_t, LogStamps>& in_memory, const std::string& source,
                            const std::string& label = "");

// {"node", "scenario", "steps", "checked", "follower_session"}: the commands' --json.
nlohmann::json to_json(const FollowedSteps& f);
// "vehicle: 1 clock step of another board taken over (seen in its kernel log) -> scenario 'k'"
std::string followed_line(const FollowedSteps& f);

}  // namespace m2mlat::analysis
