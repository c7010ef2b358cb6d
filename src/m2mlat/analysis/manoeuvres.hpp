// The manoeuvres a scenario's pairs came in: what the statistics' bootstrap resamples together.
//
// The pairs of one sweep share its command's network, execution and actuator delay, so they are not
// independent samples. A manoeuvre here is a burst of the matcher's (MatchResult::burst_gap): pairs
// whose cause edges follow each other closer than the gap. The return sweep of an across-and-back
// manoeuvre, after a hold longer than the gap, is a manoeuvre of its own; the bootstrap's blocks
// (stats/block_length.hpp) take such neighbours together when their latencies are correlated.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::analysis {

// Where each manoeuvre begins among pairs whose cause times (ns) are `cause_ns`: position 0, and every
// pair whose cause edge comes `gap` or more after the previous pair's (or before it: a file's rows out
// of time order share no manoeuvre). Empty for no pairs.
std::vector<std::size_t> manoeuvre_starts(std::span<const std::int64_t> cause_ns, core::Duration gap);

}  // namespace m2mlat::analysis
