// `m2mlat clock`: this board's clock state now: the kernel's (adjtimex), chrony's (chronyc) and
// linuxptp's (pmc) when they run; --watch repeats it (with clock step detection) until SIGINT;
// --json prints the samples as JSON (JSON Lines with --watch); --store appends them to a store
// session of their own (label "clock").
#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/store/clock_step.hpp"
#include "m2mlat/store/store.hpp"
#include "m2mlat/sync/clock_monitor.hpp"

namespace m2mlat::cli {

namespace {

struct ClockCommand {
  bool json = false, watch = false;
  std::string interval = "1s";
  std::uint64_t count = 0;
  std::string chrony = "auto", ptp = "auto";
  std::string chronyc_socket, chronyc_host;
  int chronyc_port = 0;
  std::string pmc_socket;
  std::string store_path, node;
};

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "localhost";
  return name;
}

nlohmann::json sample_json(const store::ClockSample& s) {
  return {{"source", s.source},
          {"time_ns", s.time.ns()},
          {"synchronised", s.synchronised},
          {"offset_ns", s.offset_ns},
          {"max_error_ns", s.max_error_ns},
          {"est_error_ns", s.est_error_ns},
          {"detail", nlohmann::json::parse(s.detail_json)}};
}

std::string ns_text(std::int64_t ns) { return core::format_duration(core::Duration{ns}); }

void print_sample(const store::ClockSample& s) {
  const auto d = nlohmann::json::parse(s.detail_json);
  const char* sync = s.synchronised ? "synchronised" : "NOT synchronised";
  if (s.source == "adjtimex") {
    if (d.contains("error")) {
      fmt::print("kernel:  {}\n", core::printable(d["error"].get<std::string>()));
      return;
    }
    std::string bits;
    for (const auto& b : d["status_bits"]) bits += " " + b.get<std::string>();
    fmt::print(
        "kernel:  {} ({}), offset {}, max error {}, est error {}, freq {:+.3f} ppm, status{}, TAI-UTC {} s\n",
        sync, d["state"].get<std::string>(), ns_text(s.offset_ns), ns_text(s.max_error_ns),
        ns_text(s.est_error_ns), d["freq_ppm"].get<double>(), bits.empty() ? " -" : bits,
        d["tai_s"].get<int>());
  } else if (s.source == "chrony") {
    fmt::print(
        "chrony:  {} to {} ({}), stratum {}, offset {}, max error {}, est error {}, freq {:+.3f} ppm, leap "
        "{}\n",
        sync,
        d["ref_name"].get<std::string>().empty() ? "-" : core::printable(d["ref_name"].get<std::string>()),
        core::printable(d["ref_id"].get<std::string>()), d["stratum"].get<int>(), ns_text(s.offset_ns),
        ns_text(s.max_error_ns), ns_text(s.est_error_ns), d["freq_ppm"].get<double>(),
        d["leap_status"].get<std::string>());
    for (const auto& src : d["sources"])
      fmt::print("         {}{} {} stratum {} poll {} reach {:o} offset {} +/- {}\n",
                 src["mode"].get<std::string>(), src["state"].get<std::string>(),
                 core::printable(src["name"].get<std::string>()), src["stratum"].get<int>(),
                 src["poll"].get<int>(),
                 src["reach"].get<int>(), ns_text(src["adjusted_offset_ns"].get<std::int64_t>()),
                 ns_text(src["error_ns"].get<std::int64_t>()));
  } else if (s.source == "ptp") {
    fmt::print("ptp:     {}, grandmaster {} ({} steps), master offset {}, mean path delay {}\n", sync,
               d["gm_identity"].get<std::string>(), d["steps_removed"].get<int>(), ns_text(s.offset_ns),
               ns_text(d["mean_path_delay_ns"].get<std::int64_t>()));
  } else if (s.source == "step") {
    const auto step = store::clock_step_of(s);
    fmt::print("STEP:    CLOCK_REALTIME jumped by {} at {}\n",
               step && !step->size_ns ? std::string("an unknown amount (the kernel's state was reset)")
                                      : ns_text(s.offset_ns),
               core::format_seconds(s.time.ns()));
  }
}

int run_clock(const ClockCommand& c) {
  for (const auto* v : {&c.chrony, &c.ptp})
    if (*v != "auto" && *v != "on" && *v != "off")
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("--chrony/--ptp take auto, on or off, not '{}'", *v));
  if (!c.chronyc_socket.empty() && !c.chronyc_host.empty())
    throw core::Error(core::ErrorKind::usage, "give --chronyc-socket or --chronyc-host, not both");
  const core::Duration interval = core::parse_duration(c.interval, 1'000'000'000);
  if (interval < std::chrono::milliseconds(10))
    throw core::Error(core::ErrorKind::usage, "--interval must be >= 10ms");

  sync::MonitorOptions options;
  options.kernel_interval = interval;
  if (c.chrony != "off") options.chrony_interval = interval;
  if (c.ptp != "off") options.ptp_interval = interval;
  options.chronyc.host = !c.chronyc_socket.empty() ? c.chronyc_socket : c.chronyc_host;
  options.chronyc.port = c.chronyc_port;
  options.pmc.uds = c.pmc_socket;
  sync::SystemClockSource clocks;
  process::ProcessRunner runner;
  sync::ClockMonitor monitor(options, clocks, &runner);

  std::optional<store::Store> store;
  std::int64_t session = 0;
  if (!c.store_path.empty()) {
    store.emplace(store::Store::open(c.store_path));
    store::Session s;
    s.label = "clock";
    s.node = c.node.empty() ? host_name() : c.node;
    s.role = core::Role::observer;
    s.config_json = nlohmann::json{{"kind", "clock"}, {"interval_ns", interval.count()}}.dump();
    sync::ClockPair now = sync::read_clock_pair();
    s.start = core::TimePoint::from_ns(core::Clock::realtime, now.realtime_ns);
    session = store->begin_session(s);
  }

  // In auto mode a source that does not answer is shown as such; in on mode it is an error.
  int status = 0;
  auto report = [&](std::vector<store::ClockSample>& samples, bool first) {
    if (store && !samples.empty()) store->append_clock_samples(samples);
    if (c.json && !c.watch) {
      nlohmann::json doc{{"samples", nlohmann::json::array()}, {"errors", nlohmann::json::object()}};
      for (const auto& s : samples) doc["samples"].push_back(sample_json(s));
      if (!monitor.chrony_error().empty()) doc["errors"]["chrony"] = monitor.chrony_error();
      if (!monitor.ptp_error().empty()) doc["errors"]["ptp"] = monitor.ptp_error();
      print_json(doc);
    } else if (c.json) {
      for (const auto& s : samples) fmt::print("{}\n", sample_json(s).dump());
    } else {
      for (const auto& s : samples) print_sample(s);
      if (first) {
        if (c.chrony == "auto" && !monitor.chrony_error().empty())
          fmt::print("chrony:  not available ({})\n", monitor.chrony_error());
        if (c.ptp == "auto" && !monitor.ptp_error().empty())
          fmt::print("ptp:     not available ({})\n", monitor.ptp_error());
      }
    }
    std::fflush(stdout);
    if ((c.chrony == "on" && !monitor.chrony_error().empty()) ||
        (c.ptp == "on" && !monitor.ptp_error().empty())) {
      warn(c.chrony == "on" && !monitor.chrony_error().empty() ? monitor.chrony_error()
                                                               : monitor.ptp_error());
      status = core::exit_code(core::ErrorKind::io);
    }
  };

  std::vector<store::ClockSample> samples;
  monitor.sample_all(session, samples);
  report(samples, true);
  if (c.watch) {
    capture::StopSignal stop;
    for (std::uint64_t n = 1; c.count == 0 || n < c.count; ++n) {
      pollfd pfd{stop.fd(), POLLIN, 0};
      if (::poll(&pfd, 1, static_cast<int>(interval.count() / 1'000'000)) > 0) break;
      samples.clear();
      monitor.on_batch(session, samples);
      report(samples, false);
    }
  }
  if (store)
    store->end_session(session,
                       core::TimePoint::from_ns(core::Clock::realtime, sync::read_clock_pair().realtime_ns));
  return status;
}

}  // namespace

Runner attach_clock(CLI::App& sub) {
  auto c = std::make_shared<ClockCommand>();
  sub.add_flag("--json", c->json, "Print the samples as JSON (one object per line with --watch)");
  sub.add_flag("--watch", c->watch, "Repeat every --interval until SIGINT (with clock step detection)");
  sub.add_option("--interval", c->interval, "Sampling interval with --watch (e.g. 1s, 250ms)")
      ->capture_default_str();
  sub.add_option("--count", c->count, "With --watch: stop after this many readings (0: never)");
  sub.add_option("--chrony", c->chrony, "Read chrony: auto (if it answers), on (an error if not), off")
      ->capture_default_str();
  sub.add_option("--chronyc-socket", c->chronyc_socket, "chronyd's command socket (chronyc -h PATH)");
  sub.add_option("--chronyc-host", c->chronyc_host, "chronyd's command address (chronyc -h HOST)");
  sub.add_option("--chronyc-port", c->chronyc_port, "chronyd's command port (chronyc -p PORT)");
  sub.add_option("--ptp", c->ptp, "Read ptp4l through pmc: auto, on, off")->capture_default_str();
  sub.add_option("--pmc-socket", c->pmc_socket, "ptp4l's Unix socket (pmc -s PATH)");
  sub.add_option("--store", c->store_path, "Append the samples to this store, in a session labelled 'clock'");
  sub.add_option("--node", c->node, "The node name of that session (default: the host name)");
  return [c] { return run_clock(*c); };
}

}  // namespace m2mlat::cli
