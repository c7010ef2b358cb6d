// The table of settable fields and the text conversions behind it: see overrides.hpp.
#include "m2mlat/sim/overrides.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/sim/presets.hpp"

namespace m2mlat::sim {

namespace {

using Setter = std::function<void(RigConfig&, std::string_view)>;
using Getter = std::function<std::string(const RigConfig&)>;

struct Field {
  FieldInfo info;
  Setter set;
  Getter get;
  bool shortcut = false;  // sets several fields at once; left out of describe()
};

[[noreturn]] void bad_value(std::string_view text, std::string_view expected) {
  throw core::Error(core::ErrorKind::usage, fmt::format("'{}' is not {}", text, expected));
}

double decimal_value(std::string_view text) {
  double value = 0;
  if (!core::parse_double(text, value) || !std::isfinite(value)) bad_value(text, "a decimal number");
  return value;
}

template <typename Int>
Int integer_value(std::string_view text) {
  Int value = 0;
  if (!core::parse_integer(text, value)) bad_value(text, "an integer in range");
  return value;
}

bool bool_value(std::string_view text) {
  if (text == "true") return true;
  if (text != "false") bad_value(text, "true or false");
  return false;
}

// Exact text for a duration, in the largest unit that divides it: "1500ms", "3s", "250us", "7ns".
std::string format_duration_exact(core::Duration d) {
  struct Unit {
    std::int64_t ns;
    std::string_view suffix;
  };
  static constexpr Unit kUnits[] = {{3'600'000'000'000, "h"},
                                    {60'000'000'000, "min"},
                                    {1'000'000'000, "s"},
                                    {1'000'000, "ms"},
                                    {1'000, "us"}};
  const std::int64_t ns = d.count();
  if (ns == 0) return "0s";
  if (d == core::Duration::max()) return fmt::format("{}ns", ns);
  for (const auto& unit : kUnits)
    if (ns % unit.ns == 0) return fmt::format("{}{}", ns / unit.ns, unit.suffix);
  return fmt::format("{}ns", ns);
}

std::string format_double(double value) { return fmt::format("{}", value); }

std::vector<double> parse_angles(std::string_view text) {
  std::vector<double> angles;
  while (true) {
    const auto comma = text.find(',');
    angles.push_back(decimal_value(text.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return angles;
}

std::string format_angles(const std::vector<double>& angles) {
  std::string out;
  for (double a : angles) out += (out.empty() ? "" : ",") + format_double(a);
  return out;
}

// Days since 1970-01-01 of a proleptic Gregorian date, and back. Years are counted in 400-year eras
// of 146097 days, with March as the first month so that the leap day ends the year.
std::int64_t days_from_civil(std::int64_t y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t yoe = y - era * 400;
  const std::int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

void civil_from_days(std::int64_t z, std::int64_t& y, int& m, int& d) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  d = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  m = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  y = yoe + era * 400 + (m <= 2 ? 1 : 0);
}

// Accessors: a generic lambda gives the field of a RigConfig, const or not.
#define M2MLAT_FIELD(path) \
  [](auto& c) -> auto& { return c.path; }

class Table {
 public:
  Table() {
    add_string("scenario", "name of the preset this configuration started from (free text, for reports)",
               M2MLAT_FIELD(scenario));
    add_integer<std::uint64_t>("seed", "seed of every random stream: same seed, same run",
                               M2MLAT_FIELD(seed));
    add_string("cause_node", "name of the operator's board (the cause)", M2MLAT_FIELD(cause_node));
    add_string("effect_node", "name of the vehicle's board (the effect)", M2MLAT_FIELD(effect_node));
    add_string("channel", "channel name on both boards", M2MLAT_FIELD(channel));
    fields_.push_back({{"start", "true time of the run's start, ISO-8601 UTC or epoch seconds"},
                       [](RigConfig& c, std::string_view v) {
                         c.start = core::TimePoint::from_ns(core::Clock::realtime, parse_utc(v));
                       },
                       [](const RigConfig& c) { return format_utc(c.start.ns()); }});
    add_integer<std::int64_t>("manoeuvres", "stop after this many manoeuvres (0: no limit)",
                              M2MLAT_FIELD(manoeuvres));
    add_duration("duration", "stop when the next manoeuvre would start this long after start (0s: no limit)",
                 M2MLAT_FIELD(duration));
    fields_.push_back(
        {{"magnets_deg", "magnet angles on the wheel, degrees, comma-separated (e.g. 0,120,240)"},
         [](RigConfig& c, std::string_view v) { c.magnets_deg = parse_angles(v); },
         [](const RigConfig& c) { return format_angles(c.magnets_deg); }});
    add_duration("clock_sample_interval", "record both clocks' state this often (0s: never)",
                 M2MLAT_FIELD(clock_sample_interval));

    add_duration("motion.interval_min", "shortest start-to-start time between manoeuvres",
                 M2MLAT_FIELD(motion.interval_min));
    add_duration("motion.interval_max", "longest start-to-start time between manoeuvres",
                 M2MLAT_FIELD(motion.interval_max));
    add_duration("motion.min_pause", "shortest rest of the wheel between manoeuvres",
                 M2MLAT_FIELD(motion.min_pause));
    add_double("motion.speed_min_deg_s", "slowest turning speed, deg/s",
               M2MLAT_FIELD(motion.speed_min_deg_s));
    add_double("motion.speed_max_deg_s", "fastest turning speed, deg/s",
               M2MLAT_FIELD(motion.speed_max_deg_s));
    add_double("motion.clearance_min_deg", "nearest rest position past the outermost magnet, degrees",
               M2MLAT_FIELD(motion.clearance_min_deg));
    add_double("motion.clearance_max_deg", "farthest rest position past the outermost magnet, degrees",
               M2MLAT_FIELD(motion.clearance_max_deg));
    add_double("motion.return_probability", "chance a manoeuvre turns across and straight back",
               M2MLAT_FIELD(motion.return_probability));
    add_duration("motion.hold_min", "shortest pause before a return sweep", M2MLAT_FIELD(motion.hold_min));
    add_duration("motion.hold_max", "longest pause before a return sweep", M2MLAT_FIELD(motion.hold_max));

    add_duration("station.command_period", "the station sends the wheel angle this often",
                 M2MLAT_FIELD(station.command_period));
    add_dist("station.processing", "wheel sampled -> command packet sent", M2MLAT_FIELD(station.processing));

    fields_.push_back({{"network", "replace the network profile: wifi, 5g or wired"},
                       [](RigConfig& c, std::string_view v) { c.network = network_profile(v); },
                       [](const RigConfig& c) { return c.network.name; },
                       true});
    add_dist("network.delay", "one-way delay of a delivered command packet", M2MLAT_FIELD(network.delay));
    add_double("network.burst_probability", "chance a packet also waits out a burst",
               M2MLAT_FIELD(network.burst_probability));
    add_dist("network.burst", "extra delay of a burst", M2MLAT_FIELD(network.burst));
    add_double("network.loss_probability", "chance a command packet is lost (costs a command period)",
               M2MLAT_FIELD(network.loss_probability));
    add_double("network.stall_per_minute",
               "link stalls per minute (Poisson; 0: none); nothing is delivered "
               "during a stall, the queued packets then arrive in order",
               M2MLAT_FIELD(network.stall_per_minute));
    add_dist("network.stall", "length of a stall", M2MLAT_FIELD(network.stall));
    add_duration("network.stall_drain", "after a stall, the queued packets arrive this far apart",
                 M2MLAT_FIELD(network.stall_drain));

    add_double("vehicle.moving_probability", "chance the vehicle is driving during a manoeuvre",
               M2MLAT_FIELD(vehicle.moving_probability));
    add_duration("vehicle.control_period", "period of the vehicle's control loop",
                 M2MLAT_FIELD(vehicle.control_period));
    add_dist("vehicle.execution", "command picked up -> actuator set point", M2MLAT_FIELD(vehicle.execution));
    add_dist("vehicle.actuator_lag_static", "set point -> wheel moves, vehicle standing",
             M2MLAT_FIELD(vehicle.actuator_lag_static));
    add_dist("vehicle.actuator_lag_moving", "set point -> wheel moves, vehicle driving",
             M2MLAT_FIELD(vehicle.actuator_lag_moving));
    add_double("vehicle.speed_ratio_min", "vehicle wheel speed / operator wheel speed, lowest",
               M2MLAT_FIELD(vehicle.speed_ratio_min));
    add_double("vehicle.speed_ratio_max", "vehicle wheel speed / operator wheel speed, highest",
               M2MLAT_FIELD(vehicle.speed_ratio_max));
    add_double("vehicle.max_speed_deg_s", "fastest the actuator turns the wheel, deg/s",
               M2MLAT_FIELD(vehicle.max_speed_deg_s));
    add_duration("vehicle.min_pause", "shortest rest of the vehicle's wheel between sweeps",
                 M2MLAT_FIELD(vehicle.min_pause));

    fields_.push_back(
        {{"sensor.<field>", "set <field> on both cause_sensor and effect_sensor"}, {}, {}, true});
    add_sensor("cause_sensor", "operator's", M2MLAT_FIELD(cause_sensor));
    add_sensor("effect_sensor", "vehicle's", M2MLAT_FIELD(effect_sensor));
    add_clock("cause_clock", "operator board's", M2MLAT_FIELD(cause_clock));
    add_clock("effect_clock", "vehicle board's", M2MLAT_FIELD(effect_clock));

    fields_.push_back(
        {{"sync", "replace the synchronisation set-up: co_referenced, autonomous, perfect or free"},
         [](RigConfig& c, std::string_view v) { c.sync = sync_profile(v); },
         [](const RigConfig& c) { return std::string(to_string(c.sync.mode)); },
         true});
    fields_.push_back({{"sync.mode", "synchronisation mode only: co_referenced, autonomous, perfect or free"},
                       [](RigConfig& c, std::string_view v) { c.sync.mode = parse_sync_mode(v); },
                       [](const RigConfig& c) { return std::string(to_string(c.sync.mode)); }});
    add_duration("sync.poll_interval", "one offset measurement and correction per interval",
                 M2MLAT_FIELD(sync.poll_interval));
    add_link("sync.upstream", "a board to its own time servers", M2MLAT_FIELD(sync.upstream));
    add_link("sync.peer", "the vehicle board to the operator board (co_referenced)", M2MLAT_FIELD(sync.peer));
    add_double("sync.loop_gain", "fraction of a measured offset slewed away per poll",
               M2MLAT_FIELD(sync.loop_gain));
    add_double("sync.frequency_gain", "fraction of a measured offset added to the frequency correction",
               M2MLAT_FIELD(sync.frequency_gain));
    add_double("sync.max_slew_ppm", "the fastest the daemon adjusts the clock's rate, ppm (chrony's maxslewrate)",
               M2MLAT_FIELD(sync.max_slew_ppm));
  }

  const std::vector<Field>& fields() const { return fields_; }

 private:
  template <typename Access>
  void add_duration(std::string key, std::string help, Access access) {
    fields_.push_back({{std::move(key), std::move(help) + " (duration: 800ms, 1.5s, 250us)"},
                       [access](RigConfig& c, std::string_view v) { access(c) = core::parse_duration(v); },
                       [access](const RigConfig& c) { return format_duration_exact(access(c)); }});
  }
  template <typename Access>
  void add_double(std::string key, std::string help, Access access) {
    fields_.push_back({{std::move(key), std::move(help)},
                       [access](RigConfig& c, std::string_view v) { access(c) = decimal_value(v); },
                       [access](const RigConfig& c) { return format_double(access(c)); }});
  }
  template <typename Int, typename Access>
  void add_integer(std::string key, std::string help, Access access) {
    fields_.push_back({{std::move(key), std::move(help)},
                       [access](RigConfig& c, std::string_view v) { access(c) = integer_value<Int>(v); },
                       [access](const RigConfig& c) { return fmt::format("{}", access(c)); }});
  }
  template <typename Access>
  void add_bool(std::string key, std::string help, Access access) {
    fields_.push_back({{std::move(key), std::move(help)},
                       [access](RigConfig& c, std::string_view v) { access(c) = bool_value(v); },
                       [access](const RigConfig& c) { return std::string(access(c) ? "true" : "false"); }});
  }
  template <typename Access>
  void add_string(std::string key, std::string help, Access access) {
    fields_.push_back({{std::move(key), std::move(help)},
                       [access](RigConfig& c, std::string_view v) { access(c) = std::string(v); },
                       [access](const RigConfig& c) { return std::string(access(c)); }});
  }
  template <typename Access>
  void add_dist(const std::string& key, const std::string& what, Access access) {
    fields_.push_back({{key + ".shape", what + ": shape (constant, uniform, normal, exponential, lognormal)"},
                       [access](RigConfig& c, std::string_view v) { access(c).shape = parse_shape(v); },
                       [access](const RigConfig& c) { return std::string(to_string(access(c).shape)); }});
    add_duration(
        key + ".offset", what + ": fixed part (the mean of a normal)", [access](auto& c) -> auto& {
          return access(c).offset;
        });
    add_duration(
        key + ".scale",
        what + ": random part (width, std dev, mean or median by shape)", [access](auto& c) -> auto& {
          return access(c).scale;
        });
    add_double(
        key + ".log_sigma",
        what + ": lognormal only, std dev of ln", [access](auto& c) -> auto& { return access(c).log_sigma; });
    add_duration(
        key + ".min",
        what + ": draws are at least this", [access](auto& c) -> auto& { return access(c).min; });
    add_duration(
        key + ".max",
        what + ": draws are at most this", [access](auto& c) -> auto& { return access(c).max; });
  }
  template <typename Access>
  void add_sensor(const std::string& key, const std::string& whose, Access access) {
    add_double(
        key + ".miss_probability",
        "chance the " + whose + " sensor misses a magnet pass", [access](auto& c) -> auto& {
          return access(c).miss_probability;
        });
    add_double(
        key + ".bounce_probability",
        "chance a detected pass on the " + whose + " side bounces", [access](auto& c) -> auto& {
          return access(c).bounce_probability;
        });
    add_integer<int>(
        key + ".bounce_max_extra",
        "most extra edges of one bounce", [access](auto& c) -> auto& { return access(c).bounce_max_extra; });
    add_duration(
        key + ".bounce_window",
        "bounce edges come within this time after the true edge", [access](auto& c) -> auto& {
          return access(c).bounce_window;
        });
    add_duration(
        key + ".bounce_min_gap",
        "shortest gap between bounce edges", [access](auto& c) -> auto& { return access(c).bounce_min_gap; });
    add_double(
        key + ".spurious_per_minute",
        "rate of edges no magnet caused, per minute", [access](auto& c) -> auto& {
          return access(c).spurious_per_minute;
        });
    add_dist(
        key + ".irq_latency",
        "edge -> kernel timestamp on the " + whose + " board", [access](auto& c) -> auto& {
          return access(c).irq_latency;
        });
    add_bool(
        key + ".both_edges",
        "the " + whose + " line recorded with both edges: passes and interference as pulses",
        [access](auto& c) -> auto& { return access(c).both_edges; });
    add_dist(
        key + ".dwell",
        "with both edges: how long a pass holds the " + whose + " line", [access](auto& c) -> auto& {
          return access(c).dwell;
        });
    add_dist(
        key + ".interference_width",
        "with both edges: an interference pulse's width on the " + whose + " line",
        [access](auto& c) -> auto& { return access(c).interference_width; });
  }
  template <typename Access>
  void add_clock(const std::string& key, const std::string& whose, Access access) {
    add_duration(
        key + ".initial_offset",
        "the " + whose + " clock's error at the start (free mode)", [access](auto& c) -> auto& {
          return access(c).initial_offset;
        });
    add_double(
        key + ".drift_ppm",
        "the " + whose + " oscillator's frequency error, ppm", [access](auto& c) -> auto& {
          return access(c).drift_ppm;
        });
    add_double(
        key + ".wander_ppm_per_sqrt_s",
        "random walk of that frequency error, ppm after 1 s", [access](auto& c) -> auto& {
          return access(c).wander_ppm_per_sqrt_s;
        });
    add_duration(
        key + ".sync_bias",
        "the error synchronisation leaves on average (path asymmetry)", [access](auto& c) -> auto& {
          return access(c).sync_bias;
        });
    add_duration(
        key + ".step_at", "when the " + whose + " clock is stepped, after the start", [access](auto& c) -> auto& {
          return access(c).step_at;
        });
    add_duration(
        key + ".step",
        "size of that step (new - old reading; 0s: no step); it stays", [access](auto& c) -> auto& {
          return access(c).step;
        });
  }
  template <typename Access>
  void add_link(const std::string& key, const std::string& what, Access access) {
    add_duration(
        key + ".noise",
        what + ": std dev of one offset measurement", [access](auto& c) -> auto& { return access(c).noise; });
    add_duration(
        key + ".rtt", what + ": round-trip delay", [access](auto& c) -> auto& { return access(c).rtt; });
    add_double(
        key + ".outlier_probability",
        what + ": chance a measurement is an outlier", [access](auto& c) -> auto& {
          return access(c).outlier_probability;
        });
    add_duration(
        key + ".outlier_mean",
        what + ": mean outlier size (positive pulls the clock ahead)", [access](auto& c) -> auto& {
          return access(c).outlier_mean;
        });
  }

  std::vector<Field> fields_;
};

#undef M2MLAT_FIELD

const Table& table() {
  static const Table t;
  return t;
}

const Field& find(std::string_view key) {
  for (const Field& field : table().fields())
    if (field.info.key == key && field.set) return field;
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("unknown simulator setting '{}' (see docs/simulator.md for the list)", key));
}

}  // namespace

const std::vector<FieldInfo>& settable_fields() {
  static const std::vector<FieldInfo> infos = [] {
    std::vector<FieldInfo> out;
    for (const Field& field : table().fields()) out.push_back(field.info);
    return out;
  }();
  return infos;
}

void set_field(RigConfig& config, std::string_view key, std::string_view value) {
  constexpr std::string_view kBothSensors = "sensor.";
  try {
    if (key.starts_with(kBothSensors)) {
      const std::string rest(key.substr(kBothSensors.size()));
      RigConfig copy = config;
      find("cause_sensor." + rest).set(copy, value);
      find("effect_sensor." + rest).set(copy, value);
      config = std::move(copy);
      return;
    }
    find(key).set(config, value);  // setters assign only after parsing: a failure changes nothing
    if (key.starts_with("network.")) config.network.name = "custom";
  } catch (const core::Error& e) {
    throw core::Error(core::ErrorKind::usage, fmt::format("simulator setting '{}': {}", key, e.what()));
  }
}

std::string get_field(const RigConfig& config, std::string_view key) {
  for (const Field& field : table().fields())
    if (field.info.key == key && field.get) return field.get(config);
  throw core::Error(core::ErrorKind::usage, fmt::format("unknown simulator setting '{}'", key));
}

void apply_overrides(RigConfig& config, std::span<const std::string> assignments) {
  RigConfig copy = config;
  for (const std::string& assignment : assignments) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("simulator setting '{}': expected key=value", assignment));
    set_field(copy, std::string_view(assignment).substr(0, eq), std::string_view(assignment).substr(eq + 1));
  }
  validate(copy);
  config = std::move(copy);
}

std::vector<std::pair<std::string, std::string>> describe(const RigConfig& config) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Field& field : table().fields())
    if (!field.shortcut && field.get) out.emplace_back(field.info.key, field.get(config));
  return out;
}

std::int64_t parse_utc(std::string_view text) {
  std::int64_t ns = 0;
  if (core::parse_seconds(text, ns)) return ns;
  // YYYY-MM-DDTHH:MM:SS[.f{1,9}]Z
  auto digits = [&](std::size_t pos, std::size_t count) {
    if (pos + count > text.size()) bad_value(text, "a UTC time (2026-06-01T09:00:00Z) or epoch seconds");
    return integer_value<int>(text.substr(pos, count));
  };
  if (text.size() < 20 || text[4] != '-' || text[7] != '-' || (text[10] != 'T' && text[10] != ' ') ||
      text[13] != ':' || text[16] != ':' || text.back() != 'Z')
    bad_value(text, "a UTC time (2026-06-01T09:00:00Z) or epoch seconds");
  const int year = digits(0, 4), month = digits(5, 2), day = digits(8, 2);
  const int hour = digits(11, 2), minute = digits(14, 2), second = digits(17, 2);
  if (month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 || second > 59)
    bad_value(text, "a valid UTC time");
  std::int64_t fraction_ns = 0;
  const std::string_view rest = text.substr(19, text.size() - 20);  // between the seconds and 'Z'
  if (!rest.empty()) {
    if (rest.front() != '.' || rest.size() < 2 || rest.size() > 10)
      bad_value(text, "a UTC time with 1-9 decimals");
    fraction_ns = integer_value<std::int64_t>(rest.substr(1));
    for (std::size_t i = rest.size() - 1; i < 9; ++i) fraction_ns *= 10;
  }
  std::int64_t y = 0;
  int m = 0, d = 0;
  civil_from_days(days_from_civil(year, month, day), y, m, d);
  if (m != month || d != day) bad_value(text, "a valid UTC date");
  const std::int64_t seconds = days_from_civil(year, month, day) * 86400 + hour * 3600 + minute * 60 + second;
  return seconds * 1'000'000'000 + fraction_ns;
}

std::string format_utc(std::int64_t ns) {
  std::int64_t seconds = ns / 1'000'000'000;
  std::int64_t fraction = ns % 1'000'000'000;
  if (fraction < 0) {
    fraction += 1'000'000'000;
    --seconds;
  }
  std::int64_t days = seconds / 86400;
  std::int64_t in_day = seconds % 86400;
  if (in_day < 0) {
    in_day += 86400;
    --days;
  }
  std::int64_t y = 0;
  int m = 0, d = 0;
  civil_from_days(days, y, m, d);
  std::string text = fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", y, m, d, in_day / 3600,
                                 in_day / 60 % 60, in_day % 60);
  if (fraction != 0) {
    std::string digits = fmt::format("{:09}", fraction);
    while (digits.back() == '0') digits.pop_back();
    text += "." + digits;
  }
  return text + "Z";
}

}  // namespace m2mlat::sim
