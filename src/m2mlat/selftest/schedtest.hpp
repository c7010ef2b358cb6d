// The scheduling test: cyclictest with the reference rig's settings on the capture core, its
// result as JSON, as text, and stored. A schedtest is not a clock measurement and has no events, so
// it is kept as its own store session: node = this board, label "schedtest", role observer, start
// and end = the run, and the whole result in the session's config_json ({"kind": "schedtest", ...}).
// Nothing else in the store changes, and any reader of sessions finds it.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "m2mlat/core/time.hpp"
#include "m2mlat/selftest/cyclictest.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::selftest {

inline constexpr std::string_view kSchedtestLabel = "schedtest";

struct SchedtestRun {
  CyclictestOptions options;
  CyclictestResult result;
  core::TimePoint start, end;  // CLOCK_REALTIME around the run
};

// Runs cyclictest with `options` (see run_cyclictest), timing it.
SchedtestRun run_schedtest(process::CommandRunner& runner, const CyclictestOptions& options);

// The result as stored in config_json and printed by --json.
nlohmann::json schedtest_json(const SchedtestRun& run);
// min/avg/max per thread and the histogram as text bars (non-empty buckets), for the terminal.
std::string schedtest_text(const SchedtestRun& run);
// Stores the run as a closed session of `node` (see above); returns its id.
std::int64_t store_schedtest(store::Store& store, const std::string& node, const SchedtestRun& run);

}  // namespace m2mlat::selftest
