// Parsing pmc's text output and turning ptp4l's state into clock samples.
#include "m2mlat/sync/ptp.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "m2mlat/core/number.hpp"
#include "m2mlat/core/saturating.hpp"
#include "m2mlat/sync/text.hpp"

namespace m2mlat::sync {

std::vector<PmcResponse> parse_pmc_output(std::string_view text, const core::Location& where) {
  std::vector<PmcResponse> out;
  core::Location at = where;
  at.line = 0;
  for (const auto line : text::lines(text)) {
    ++at.line;
    const auto trimmed = text::trim(line);
    if (trimmed.empty() || trimmed.starts_with("sending:")) continue;
    const auto w = text::words(trimmed);
    const bool field_line = line.starts_with("\t\t") || line.starts_with("    ");
    if (!field_line && w.size() >= 6 && w[1] == "seq" && w[4] == "MANAGEMENT") {
      PmcResponse r;
      r.port_identity = std::string(w[0]);
      if (!core::parse_integer(w[2], r.seq))
        core::throw_data_error(at, "seq " + text::quoted(w[2]) + " is not an integer");
      r.action = std::string(w[3]);
      r.id = std::string(w[5]);
      out.push_back(std::move(r));
    } else if (field_line && !out.empty()) {
      const auto name = w.at(0);
      const auto value = text::trim(trimmed.substr(name.size()));
      out.back().fields[std::string(name)] = std::string(value);
    } else {
      core::throw_data_error(at, text::quoted(trimmed) + " is neither a response header nor a field");
    }
  }
  return out;
}

namespace {

const PmcResponse& find(const std::vector<PmcResponse>& responses, std::string_view id,
                        const core::Location& where) {
  for (const auto& r : responses)
    if (r.id == id && r.action == "RESPONSE") return r;
  core::throw_data_error(where, fmt::format("no {} response (is ptp4l running?)", id));
}

std::string_view field(const PmcResponse& r, const std::string& name, const core::Location& where) {
  const auto it = r.fields.find(name);
  if (it == r.fields.end()) core::throw_data_error(where, fmt::format("{}: no field '{}'", r.id, name));
  return it->second;
}

std::int64_t int_field(const PmcResponse& r, const std::string& name, const core::Location& where) {
  std::int64_t v = 0;
  const auto text = field(r, name, where);
  if (!core::parse_integer(text, v))
    core::throw_data_error(
        where, fmt::format("{}: field '{}': {} is not an integer", r.id, name, text::quoted(text)));
  return v;
}

// pmc prints TimeInterval values (scaled ns / 2^16) as ns with one decimal: rounded to whole ns.
std::int64_t ns_field(const PmcResponse& r, const std::string& name, const core::Location& where) {
  double v = 0;
  const auto text = field(r, name, where);
  if (!core::parse_double(text, v) || !std::isfinite(v) || std::fabs(v) > 9.2e18)
    core::throw_data_error(
        where, fmt::format("{}: field '{}': {} is not a number of ns", r.id, name, text::quoted(text)));
  return std::llround(v);
}

}  // namespace

PtpStatus ptp_status(const std::vector<PmcResponse>& responses, const core::Location& where) {
  const PmcResponse& ts = find(responses, "TIME_STATUS_NP", where);
  const PmcResponse& cds = find(responses, "CURRENT_DATA_SET", where);
  PtpStatus s;
  s.port_identity = ts.port_identity;
  const auto gm = field(ts, "gmPresent", where);
  if (gm != "true" && gm != "false")
    core::throw_data_error(where,
                           "TIME_STATUS_NP: field 'gmPresent': " + text::quoted(gm) + " is not true/false");
  s.gm_present = gm == "true";
  s.gm_identity = std::string(field(ts, "gmIdentity", where));
  s.master_offset_ns = int_field(ts, "master_offset", where);
  s.ingress_time_ns = int_field(ts, "ingress_time", where);
  const std::int64_t steps = int_field(cds, "stepsRemoved", where);
  if (steps < 0 || steps > 65535)
    core::throw_data_error(where, "CURRENT_DATA_SET: field 'stepsRemoved' is out of range");
  s.steps_removed = static_cast<int>(steps);
  s.mean_path_delay_ns = ns_field(cds, "meanPathDelay", where);
  return s;
}

store::ClockSample ptp_sample(const PtpStatus& status, core::TimePoint time) {
  store::ClockSample sample;
  sample.time = time;
  sample.source = "ptp";
  sample.offset_ns = status.master_offset_ns;
  const std::int64_t abs_offset = core::saturating_abs(status.master_offset_ns);
  sample.max_error_ns = core::saturating_add(abs_offset, core::saturating_abs(status.mean_path_delay_ns));
  sample.est_error_ns = abs_offset;
  sample.synchronised = status.gm_present && status.steps_removed >= 1;
  sample.detail_json = nlohmann::json{{"port_identity", status.port_identity},
                                      {"gm_present", status.gm_present},
                                      {"gm_identity", status.gm_identity},
                                      {"master_offset_ns", status.master_offset_ns},
                                      {"ingress_time_ns", status.ingress_time_ns},
                                      {"steps_removed", status.steps_removed},
                                      {"mean_path_delay_ns", status.mean_path_delay_ns}}
                           // identities are pmc's text: bytes that are not UTF-8 become U+FFFD
                           .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return sample;
}

std::vector<std::string> pmc_argv(const PmcOptions& options) {
  std::vector<std::string> argv{options.program, "-u", "-b", "0"};
  if (!options.uds.empty()) {
    argv.push_back("-s");
    argv.push_back(options.uds);
  }
  if (options.domain >= 0) {
    argv.push_back("-d");
    argv.push_back(std::to_string(options.domain));
  }
  argv.push_back("GET TIME_STATUS_NP");
  argv.push_back("GET CURRENT_DATA_SET");
  return argv;
}

PtpStatus read_ptp(process::CommandRunner& runner, const PmcOptions& options) {
  const auto argv = pmc_argv(options);
  const process::CommandResult r = runner.run(argv, options.timeout);
  if (!r.ok()) throw process::command_error(argv, r);
  const core::Location where{process::command_line(argv), 0};
  const auto responses = parse_pmc_output(r.out, where);
  if (responses.empty())
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: no answer (is ptp4l running?)", process::command_line(argv)));
  return ptp_status(responses, where);
}

}  // namespace m2mlat::sync
