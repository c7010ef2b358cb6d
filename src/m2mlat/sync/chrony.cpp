// Parsing chronyc's CSV output and turning it into clock samples.
#include "m2mlat/sync/chrony.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <nlohmann/json.hpp>

#include "m2mlat/core/number.hpp"
#include "m2mlat/core/saturating.hpp"
#include "m2mlat/sync/text.hpp"

namespace m2mlat::sync {

namespace {

constexpr std::size_t kTrackingFields = 14;
constexpr std::size_t kSourceFields = 10;

// Reads the fields of one line, naming the field in every error.
class Fields {
 public:
  Fields(std::vector<std::string_view> fields, const core::Location& where)
      : f_(std::move(fields)), where_(where) {}

  [[noreturn]] void fail(std::string_view name, std::string_view what) const {
    core::throw_data_error(where_, fmt::format("field '{}': {}", name, what));
  }
  std::string_view at(std::size_t i) const { return f_.at(i); }
  std::int64_t integer(std::size_t i, std::string_view name, int base = 10) const {
    std::int64_t v = 0;
    if (!core::parse_integer(f_.at(i), v, base)) fail(name, text::quoted(f_.at(i)) + " is not an integer");
    return v;
  }
  int small_int(std::size_t i, std::string_view name, std::int64_t lo, std::int64_t hi, int base = 10) const {
    const std::int64_t v = integer(i, name, base);
    if (v < lo || v > hi) fail(name, fmt::format("{} is out of range [{}, {}]", v, lo, hi));
    return static_cast<int>(v);
  }
  std::int64_t seconds(std::size_t i, std::string_view name) const {
    std::int64_t ns = 0;
    if (!core::parse_seconds(f_.at(i), ns))
      fail(name, text::quoted(f_.at(i)) + " is not a number of seconds");
    return ns;
  }
  double real(std::size_t i, std::string_view name) const {
    double v = 0;
    if (!core::parse_double(f_.at(i), v)) fail(name, text::quoted(f_.at(i)) + " is not a number");
    return v;
  }
  char symbol(std::size_t i, std::string_view name, std::string_view allowed) const {
    const auto s = f_.at(i);
    if (s.size() != 1 || allowed.find(s[0]) == std::string_view::npos)
      fail(name, text::quoted(s) + " is not one of " + std::string(allowed));
    return s[0];
  }

 private:
  std::vector<std::string_view> f_;
  core::Location where_;
};

std::vector<std::string_view> checked_split(std::string_view line, std::size_t want, std::string_view what,
                                            const core::Location& where) {
  auto fields = text::split(text::trim(line), ',');
  if (fields.size() != want)
    core::throw_data_error(where,
                           fmt::format("{} line has {} fields, expected {}", what, fields.size(), want));
  return fields;
}

}  // namespace

ChronyTracking parse_chrony_tracking_line(std::string_view line, const core::Location& where) {
  const Fields f(checked_split(line, kTrackingFields, "chronyc tracking", where), where);
  ChronyTracking t;
  const auto id = f.at(0);
  if (id.size() != 8) f.fail("reference id", text::quoted(id) + " is not 8 hexadecimal digits");
  t.ref_id = static_cast<std::uint32_t>(f.integer(0, "reference id", 16));
  t.ref_name = std::string(f.at(1));
  t.stratum = f.small_int(2, "stratum", 0, 16);
  t.ref_time_ns = f.seconds(3, "ref time");
  t.system_offset_ns = -f.seconds(4, "system time");
  t.last_offset_ns = f.seconds(5, "last offset");
  t.rms_offset_ns = f.seconds(6, "rms offset");
  t.freq_ppm = f.real(7, "frequency");
  t.residual_freq_ppm = f.real(8, "residual freq");
  t.skew_ppm = f.real(9, "skew");
  t.root_delay_ns = f.seconds(10, "root delay");
  t.root_dispersion_ns = f.seconds(11, "root dispersion");
  t.update_interval_ns = f.seconds(12, "update interval");
  const auto leap = f.at(13);
  if (leap != "Normal" && leap != "Insert second" && leap != "Delete second" && leap != "Not synchronised" &&
      leap != "Invalid")
    f.fail("leap status", text::quoted(leap) + " is not a chrony leap status");
  t.leap_status = std::string(leap);
  if (t.rms_offset_ns < 0) f.fail("rms offset", "is negative");
  if (t.root_delay_ns < 0) f.fail("root delay", "is negative");
  if (t.root_dispersion_ns < 0) f.fail("root dispersion", "is negative");
  return t;
}

ChronySource parse_chrony_source_line(std::string_view line, const core::Location& where) {
  const Fields f(checked_split(line, kSourceFields, "chronyc sources", where), where);
  ChronySource s;
  s.mode = f.symbol(0, "mode", "^=#");
  s.state = f.symbol(1, "state", "*+-x~?");
  s.name = std::string(f.at(2));
  if (s.name.empty()) f.fail("name", "is empty");
  s.stratum = f.small_int(3, "stratum", 0, 16);
  s.poll = f.small_int(4, "poll", -32, 32);
  s.reach = f.small_int(5, "reach", 0, 0377, 8);
  const std::int64_t last_rx = f.integer(6, "last rx");
  if (last_rx < 0 || last_rx > 4294967295) f.fail("last rx", "is out of range");
  if (last_rx != 4294967295) s.last_rx_s = last_rx;  // (uint32_t)-1: no sample yet
  s.adjusted_offset_ns = f.seconds(7, "adjusted offset");
  s.measured_offset_ns = f.seconds(8, "measured offset");
  s.error_ns = f.seconds(9, "error");
  if (s.error_ns < 0) f.fail("error", "is negative");
  return s;
}

ChronyReport parse_chronyc_output(std::string_view text, const core::Location& where) {
  ChronyReport report;
  bool have_tracking = false;
  core::Location at = where;
  at.line = 0;
  for (const auto line : text::lines(text)) {
    ++at.line;
    const auto trimmed = text::trim(line);
    if (trimmed.empty()) continue;
    const std::size_t n = text::split(trimmed, ',').size();
    if (n == kTrackingFields) {
      if (have_tracking) core::throw_data_error(at, "a second tracking line");
      report.tracking = parse_chrony_tracking_line(trimmed, at);
      have_tracking = true;
    } else if (n == kSourceFields) {
      report.sources.push_back(parse_chrony_source_line(trimmed, at));
    } else {
      core::throw_data_error(
          at, fmt::format("{} is neither a tracking line ({} fields) nor a source line ({} fields)",
                          text::quoted(trimmed), kTrackingFields, kSourceFields));
    }
  }
  if (!have_tracking) {
    at.line = 0;
    core::throw_data_error(at, "no tracking line");
  }
  return report;
}

store::ClockSample chrony_sample(const ChronyReport& report, core::TimePoint time) {
  const ChronyTracking& t = report.tracking;
  store::ClockSample sample;
  sample.time = time;
  sample.source = "chrony";
  sample.offset_ns = t.system_offset_ns;
  const std::int64_t abs_offset = core::saturating_abs(t.system_offset_ns);
  sample.max_error_ns =
      core::saturating_add(core::saturating_add(abs_offset, t.root_dispersion_ns), t.root_delay_ns / 2);
  sample.est_error_ns = std::max(t.rms_offset_ns, abs_offset);
  sample.synchronised = t.synchronised();
  nlohmann::json sources = nlohmann::json::array();
  for (const auto& s : report.sources) {
    sources.push_back({{"mode", std::string(1, s.mode)},
                       {"state", std::string(1, s.state)},
                       {"name", s.name},
                       {"stratum", s.stratum},
                       {"poll", s.poll},
                       {"reach", s.reach},
                       {"last_rx_s", s.last_rx_s ? nlohmann::json(*s.last_rx_s) : nlohmann::json()},
                       {"adjusted_offset_ns", s.adjusted_offset_ns},
                       {"measured_offset_ns", s.measured_offset_ns},
                       {"error_ns", s.error_ns}});
  }
  const nlohmann::json detail{{"ref_id", fmt::format("{:08X}", t.ref_id)},
                              {"ref_name", t.ref_name},
                              {"stratum", t.stratum},
                              {"ref_time_ns", t.ref_time_ns},
                              {"system_offset_ns", t.system_offset_ns},
                              {"last_offset_ns", t.last_offset_ns},
                              {"rms_offset_ns", t.rms_offset_ns},
                              {"freq_ppm", t.freq_ppm},
                              {"residual_freq_ppm", t.residual_freq_ppm},
                              {"skew_ppm", t.skew_ppm},
                              {"root_delay_ns", t.root_delay_ns},
                              {"root_dispersion_ns", t.root_dispersion_ns},
                              {"update_interval_ns", t.update_interval_ns},
                              {"leap_status", t.leap_status},
                              {"sources", sources}};
  // Names come from another program's output: bytes that are not UTF-8 become U+FFFD, not a throw.
  sample.detail_json = detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return sample;
}

std::vector<std::string> chronyc_argv(const ChronycOptions& options) {
  std::vector<std::string> argv{options.program, "-c", "-n", "-m"};
  if (!options.host.empty()) {
    argv.push_back("-h");
    argv.push_back(options.host);
  }
  if (options.port > 0) {
    argv.push_back("-p");
    argv.push_back(std::to_string(options.port));
  }
  argv.push_back("tracking");
  argv.push_back("sources");
  return argv;
}

ChronyReport read_chrony(process::CommandRunner& runner, const ChronycOptions& options) {
  const auto argv = chronyc_argv(options);
  const process::CommandResult r = runner.run(argv, options.timeout);
  if (!r.ok()) throw process::command_error(argv, r);
  return parse_chronyc_output(r.out, core::Location{process::command_line(argv), 0});
}

}  // namespace m2mlat::sync
