// Setting single fields of a RigConfig from text ("key=value"), as a command line or a file would:
// one declarative table of every settable field with its unit and meaning, from which the setters,
// the getters and the help are all derived (like linuxptp's option table).
//
// Keys follow the structure: "seed", "magnets_deg", "motion.interval_min", "network.loss_probability",
// "vehicle.actuator_lag_static.offset", "effect_sensor.bounce_probability", "sync.peer.noise" ...
// Shortcuts: "network=5g" and "sync=autonomous" replace a whole profile; "sensor.<field>" sets the
// field on both sensors. Values: durations with a unit ("800ms", "1.5s", "250us"), plain decimal
// numbers, comma-separated angle lists ("0,120,240"), times as ISO-8601 UTC
// ("2026-06-01T09:00:00Z") or epoch seconds ("1780304400.25").
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "m2mlat/sim/rig_config.hpp"

namespace m2mlat::sim {

struct FieldInfo {
  std::string key;
  std::string help;  // meaning and unit, one line
};

// Every settable key, in a stable order (shortcuts included).
const std::vector<FieldInfo>& settable_fields();

// Sets one field. Throws core::Error(usage) naming the key for an unknown key or a bad value; on
// error `config` is unchanged. Does not check the whole configuration (see validate()).
void set_field(RigConfig& config, std::string_view key, std::string_view value);
// The field's current value as text that set_field accepts back.
std::string get_field(const RigConfig& config, std::string_view key);

// Applies "key=value" assignments in order, then validates the result; all or nothing: on any
// error `config` is unchanged and the exception names the assignment.
void apply_overrides(RigConfig& config, std::span<const std::string> assignments);

// Every field (shortcuts excluded) with its current value, in table order: for reports and logs.
std::vector<std::pair<std::string, std::string>> describe(const RigConfig& config);

// Times: ISO-8601 UTC with optional fraction ("2026-06-01T09:00:00.5Z") or decimal epoch seconds,
// to and from CLOCK_REALTIME nanoseconds. parse_utc throws core::Error(usage).
std::int64_t parse_utc(std::string_view text);
std::string format_utc(std::int64_t ns);

}  // namespace m2mlat::sim
