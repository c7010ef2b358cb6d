// `m2mlat agent`: one node's recorder with the agent HTTP API (docs/api.md). Takes the options of
// `m2mlat record` (a TOML configuration or flags; the sim source is always paced and, unless
// --sim-set manoeuvres=N says otherwise, practically endless) plus where to listen, the bearer token and TLS.
// With --mark-port, software markers (m2mlat-mark/1 datagrams) are stamped on arrival and stored in the
// open session (/v1/markers; `marks HOST:PORT` is printed after `listening`).
// With --gyro, the gyroscope's raw samples are stored in the session they were sampled in and served
// as rate blocks (/v1/rate-blocks).
// Prints `listening HOST:PORT` on stdout once the port is bound (--listen 127.0.0.1:0 picks a free
// one; --port-file also writes the port), and stops cleanly on SIGINT/SIGTERM, committing what it has.
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <optional>

#include "m2mlat/agent/agent.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/host_port.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/cli/record_setup.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/net/auth.hpp"

namespace m2mlat::cli {

namespace {

struct AgentCommand {
  RecordFlags record;
  std::string listen = "127.0.0.1:8470";
  std::string token_file, tls_cert, tls_key, port_file;
  std::size_t max_connections = 256;
  std::optional<int> mark_port;  // the software markers' UDP port (docs/markers.md)
  std::string mark_address = "127.0.0.1";
  std::string mark_port_file;
};

int run_agent(AgentCommand& c) {
  auto& flags = c.record;
  flags.sim_paced = true;  // an agent is live: the simulated rig runs in real time
  flags.sim_set.insert(flags.sim_set.begin(), "manoeuvres=1000000000");  // years of manoeuvres
  // First, as in `record` (cmd_record.cpp): a stop during the start is seen at the first poll, and
  // every thread started later blocks the signals.
  capture::StopSignal stop;
  auto setup = prepare_record(flags);
  if (!flags.quiet)
    for (const auto& line : setup.source->describe())
      fmt::print(stderr, "m2mlat: {}\n", core::printable(line));

  agent::AgentOptions options;
  options.store_path = flags.store_path;
  options.store_options = setup.store_options;
  options.recorder = setup.options;
  const auto [host, port] = split_host_port("--listen", c.listen, "127.0.0.1:8470 or [::1]:0", true);
  options.server.host = host;
  options.server.port = port;
  options.server.token = net::load_token(c.token_file.empty() ? std::nullopt : std::optional(c.token_file));
  options.server.tls_cert = c.tls_cert;
  options.server.tls_key = c.tls_key;
  options.server.max_connections = c.max_connections;
  if (c.mark_port) options.marks = agent::AgentOptions::MarkPort{c.mark_address, *c.mark_port};
  else if (!c.mark_port_file.empty())
    throw core::Error(core::ErrorKind::usage, "--mark-port-file needs --mark-port");

  // The gyroscope's sampler runs across sessions; its samples go to the session they were sampled
  // in (capture/raw_round.hpp), those between sessions to none.
  if (setup.gyro) setup.gyro->start();
  agent::Agent agent(options, *setup.source);
  agent.start();
  if (!c.port_file.empty()) {
    core::write_output_file(c.port_file, fmt::format("{}\n", agent.port()));
  }
  fmt::print("listening {}\n", agent.address());
  if (options.marks) {
    if (!c.mark_port_file.empty()) {
      const auto colon = agent.mark_address().rfind(':');
      core::write_output_file(c.mark_port_file, fmt::format("{}\n", agent.mark_address().substr(colon + 1)));
    }
    fmt::print("marks {}\n", agent.mark_address());
  }
  std::fflush(stdout);
  if (!flags.quiet)
    fmt::print(stderr, "m2mlat: agent of node {} on {}://{}{}\n", core::printable(setup.node),
               agent.tls() ? "https" : "http", agent.address(),
               options.server.token ? " (bearer token required)" : "");
  apply_rt(setup, flags.quiet);
  const auto counters = agent.run(stop.fd(), [&] { return stop.take(); });
  warn_after_run(setup);
  if (!flags.quiet) {
    // What "dropped" means, where there were any: nothing lost, but nothing a session holds either.
    const char* why = counters.dropped == 0 ? ""
                                            : " (edges read while no session was open, before the first "
                                              "began or after a stop: not stored)";
    fmt::print(stderr, "m2mlat: {}: {} events stored, {} dropped{}, last seq {}, stopped by {}\n",
               core::printable(flags.store_path), counters.events, counters.dropped, why,
               counters.last_committed_seq, counters.stop_reason);
  }
  return 0;
}

}  // namespace

Runner attach_agent(CLI::App& sub) {
  auto c = std::make_shared<AgentCommand>();
  add_record_options(sub, c->record);
  sub.add_option("--listen", c->listen, "HOST:PORT to serve the API on (port 0: any free one)")
      ->capture_default_str();
  sub.add_option("--token-file", c->token_file,
                 "File holding the bearer token (else env M2MLAT_TOKEN); needed off loopback");
  sub.add_option("--tls-cert", c->tls_cert, "PEM certificate: serve HTTPS");
  sub.add_option("--tls-key", c->tls_key, "PEM private key of --tls-cert");
  sub.add_option("--port-file", c->port_file, "Write the bound port to this file");
  sub.add_option("--mark-port", c->mark_port,
                 "UDP port for software markers (m2mlat-mark/1 datagrams, `m2mlat mark`; 0: any free one)")
      ->check(CLI::Range(0, 65535));
  sub.add_option("--mark-address", c->mark_address,
                 "Numeric address the marker port is bound to (0.0.0.0 or :: accepts other machines' marks)")
      ->capture_default_str();
  sub.add_option("--mark-port-file", c->mark_port_file, "Write the bound marker port to this file");
  sub.add_option("--max-connections", c->max_connections,
                 "Connections open at once (a thread each); beyond, the longest idle one is closed")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}))
      ->capture_default_str();
  return [c] { return run_agent(*c); };
}

}  // namespace m2mlat::cli
