// linuxptp's view of the clock, read with `pmc -u -b 0 'GET TIME_STATUS_NP' 'GET CURRENT_DATA_SET'`
// (the management client talking to ptp4l over its Unix socket).
//
// pmc's text output (linuxptp 3.1, pmc_common.c / pmc.c) is one block per response:
//   sending: GET TIME_STATUS_NP
//   \t<port identity> seq <n> RESPONSE MANAGEMENT <ID>
//   \t\t<field name>   <value>
// e.g. TIME_STATUS_NP: master_offset (ns, integer; slave - master), ingress_time (ns since the
// epoch), cumulativeScaledRateOffset, scaledLastGmPhaseChange, gmTimeBaseIndicator,
// lastGmPhaseChange, gmPresent (true/false), gmIdentity; CURRENT_DATA_SET: stepsRemoved,
// offsetFromMaster (ns, one decimal), meanPathDelay (ns, one decimal). pmc exits 0 even when
// nothing answered (no ptp4l): then there is no response block, which is an error here.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/process/command_runner.hpp"

namespace m2mlat::sync {

struct PmcResponse {
  std::string port_identity;  // e.g. "22b6a3.fffe.ba92f9-0"
  std::int64_t seq = 0;
  std::string action;                         // "RESPONSE" (or "GET"/"SET"/"COMMAND"/"ACKNOWLEDGE" echoes)
  std::string id;                             // management id, e.g. "TIME_STATUS_NP"
  std::map<std::string, std::string> fields;  // field name -> its value text
};

// Pure parser (no I/O), for tests and fuzzing: every response block; "sending:" lines are skipped.
// Errors: core::Error(data) naming the line.
std::vector<PmcResponse> parse_pmc_output(std::string_view text, const core::Location& where);

struct PtpStatus {
  std::string port_identity;
  bool gm_present = false;
  std::string gm_identity;
  std::int64_t master_offset_ns = 0;    // this clock - the master's, ns (positive = ahead)
  std::int64_t ingress_time_ns = 0;     // when the last sync message arrived, ns since the epoch
  int steps_removed = 0;                // 0: this clock is the grandmaster (or has none)
  std::int64_t mean_path_delay_ns = 0;  // ns (rounded from pmc's one decimal)
};

// Takes TIME_STATUS_NP and CURRENT_DATA_SET out of the responses. Throws core::Error(data) when one
// is missing or a field does not parse.
PtpStatus ptp_status(const std::vector<PmcResponse>& responses, const core::Location& where);

// The status as a clock sample (source "ptp") taken at `time`:
//   offset_ns    = master_offset
//   max_error_ns = |master_offset| + mean path delay (a path asymmetry can hide up to the whole
//                  one-way delay, which the mean path delay bounds)
//   est_error_ns = |master_offset|
//   synchronised = a grandmaster is present and this clock is at least one step from it
store::ClockSample ptp_sample(const PtpStatus& status, core::TimePoint time);

struct PmcOptions {
  std::string program = "pmc";
  std::string uds;  // -s: ptp4l's Unix socket; empty: pmc's default (/var/run/ptp4l)
  int domain = -1;  // -d: PTP domain; -1: pmc's default (0)
  core::Duration timeout = std::chrono::seconds(2);
};
std::vector<std::string> pmc_argv(const PmcOptions& options);
// Runs pmc and parses its output. Throws core::Error(io) when pmc cannot be run, fails or nothing
// answered; core::Error(data) when the output does not parse.
PtpStatus read_ptp(process::CommandRunner& runner, const PmcOptions& options);

}  // namespace m2mlat::sync
