// `m2mlat collect`: the coordinator. Pulls every agent (--agent URL, one per board) into one
// campaign store, exactly once, resuming from the store's cursors after any disconnect or restart;
// optionally begins a session on every agent at start and stops them at the end. Runs until
// SIGINT/SIGTERM or --duration (or, with --once, until every agent is caught up), printing a line
// per pull error and per change of an agent's health, then a summary per agent.
#include <fmt/format.h>
#include <poll.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <utility>

#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/live_flags.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/collect/coordinator.hpp"
#include "m2mlat/collect/live_view.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::cli {

namespace {

struct CollectCommand {
  std::vector<std::string> agents;
  std::string store_path, label, scenario, duration, token_file, ca_file;
  std::string stale_after = "3s", refresh = "250ms", connect_timeout = "2s", read_timeout = "5s", poll = "0";
  std::string durability = "normal";
  bool start_session = false, stop_session = false, once = false, json = false, quiet = false;
  LiveFlags live;  // the terminal block and the dashboard (docs/dashboard.md)
};

std::chrono::milliseconds to_ms(core::Duration d) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(d);
}

nlohmann::json health_json(const collect::NodeHealth& h) {
  nlohmann::json j{{"node", h.node},
                   {"url", h.url},
                   {"role", core::to_string(h.role)},
                   {"state", collect::to_string(h.state)},
                   {"last_contact_ns", h.last_contact_ns},
                   {"events_per_s", h.events_per_s},
                   {"events", h.events},
                   {"cursor_seq", h.cursor_seq},
                   {"agent_last_seq", h.agent_last_seq},
                   {"lost", h.lost},
                   {"last_error", h.last_error}};
  if (h.has_clock) {
    j["clock"] = {{"offset_ns", h.clock_offset_ns},
                  {"max_error_ns", h.clock_max_error_ns},
                  {"synchronised", h.synchronised}};
  } else {
    j["clock"] = nullptr;
  }
  return j;
}

void print_summary(const std::vector<collect::NodeHealth>& health, const std::string& store_path, bool json) {
  if (json) {
    nlohmann::json j{{"store", store_path}, {"agents", nlohmann::json::array()}};
    for (const auto& h : health) j["agents"].push_back(health_json(h));
    print_json(j);
    return;
  }
  fmt::print("{}: {} agent(s)\n", core::printable(store_path), health.size());
  fmt::print("  {:<12} {:<7} {:<12} {:>10} {:>12} {:>12} {:>8}  {}\n", "node", "role", "state", "events",
             "stored up to", "agent last", "lost", "url");
  for (const auto& h : health)
    fmt::print("  {:<12} {:<7} {:<12} {:>10} {:>12} {:>12} {:>8}  {}\n",
               h.node.empty() ? "?" : core::printable(h.node),
               core::to_string(h.role), collect::to_string(h.state), h.events, h.cursor_seq, h.agent_last_seq,
               h.lost, core::printable(h.url));
}

int run_collect(const CollectCommand& c) {
  collect::CoordinatorOptions options;
  options.agents = c.agents;
  options.store_path = c.store_path;
  options.durability = store::parse_durability(c.durability);
  // The agents' token, by the agent's own rules: --token-file, else $M2MLAT_TOKEN.
  options.client.token = token_flag_or_env(c.token_file);
  options.client.ca_file = c.ca_file;
  options.client.connect_timeout = to_ms(core::parse_duration(c.connect_timeout, 1'000'000));
  options.client.read_timeout = to_ms(core::parse_duration(c.read_timeout, 1'000'000));
  options.stale_after = core::parse_duration(c.stale_after, 1'000'000);
  options.poll_interval = to_ms(core::parse_duration(c.poll, 1'000'000));
  if (options.client.read_timeout.count() < 1500)
    throw core::Error(core::ErrorKind::usage,
                      "--read-timeout must exceed the agent's 1 s keep-alive: use 1.5s or more");
  if (c.start_session) options.start_session = collect::NewSession{c.label, c.scenario};
  options.stop_session = c.stop_session;
  const auto refresh = to_ms(core::parse_duration(c.refresh, 1'000'000));
  if (refresh.count() < 10) throw core::Error(core::ErrorKind::usage, "--refresh must be at least 10ms");
  std::optional<core::Duration> duration;
  if (!c.duration.empty()) duration = core::parse_duration(c.duration);

  const bool quiet = c.quiet;
  const auto on_error = [](const std::string& /*url*/, const std::string& message) {
    fmt::print(stderr, "m2mlat: collect: {}\n", core::printable(message));
  };

  // Signals are blocked before any thread starts, so that every thread inherits the mask and
  // SIGINT/SIGTERM reach only the descriptor below.
  capture::StopSignal stop;
  // The live views' flags are read (a stage rule parsed) before anything is created or begun: a bad
  // one is a usage error that leaves no store and no session behind.
  auto live_options = c.live.options(c.store_path, options.client.token, !c.json);
  // The run begun here is what the live views show, whatever session an agent that restarts opens
  // before it rejoins the run.
  if (c.start_session && live_options.pairing.scenario.empty())
    live_options.pairing.scenario = c.scenario.empty() ? store::kUnnamedScenario : c.scenario;
  collect::Coordinator coordinator(options, on_error);

  if (c.once) {
    coordinator.collect_once();
    print_summary(coordinator.health(), c.store_path, c.json);
    return 0;
  }

  for (const auto& session : coordinator.start())
    if (!quiet)
      fmt::print(stderr, "m2mlat: collect: {} began session {} ('{}', '{}')\n", core::printable(session.node),
                 session.id, core::printable(session.label), core::printable(session.scenario));

  // ---- The live views: live pairing of the campaign store, the terminal block (not with --json,
  // whose stdout is the summary) and the dashboard, fed with the agents' health every --refresh.
  collect::LiveView view(std::move(live_options));
  if (const auto url = view.dashboard_url(); !url.empty()) {
    fmt::print(stderr, "dashboard {}\n", url);
    std::fflush(stderr);
  }
  std::vector<collect::NodeState> previous(c.agents.size(), collect::NodeState::unreachable);
  std::vector<bool> seen(c.agents.size(), false);
  const auto on_refresh = [&] {
    const auto health = coordinator.health();
    view.refresh(health, core::now_ns(CLOCK_REALTIME));
    for (std::size_t i = 0; i < health.size(); ++i) {
      const auto& h = health[i];
      if (seen[i] && h.state == previous[i]) continue;
      if (!seen[i] && h.state == collect::NodeState::unreachable && h.last_error.empty()) continue;
      if (!quiet || h.state != collect::NodeState::ok)
        fmt::print(
            stderr, "m2mlat: collect: {} ({}) is {}{}\n", core::printable(h.url),
            h.node.empty() ? "?" : core::printable(h.node),
            collect::to_string(h.state),
            h.state == collect::NodeState::stale
                ? fmt::format(" (no answer for {})", core::format_duration(core::Duration(
                                                         core::now_ns(CLOCK_REALTIME) - h.last_contact_ns)))
                : std::string());
      previous[i] = h.state;
      seen[i] = true;
    }
  };
  // ---- end of the live views' place -----------------------------------------------------------

  const auto started = std::chrono::steady_clock::now();
  std::string reason = "end of --duration";
  for (;;) {
    pollfd fd{stop.fd(), POLLIN, 0};
    const int ready = ::poll(&fd, 1, static_cast<int>(refresh.count()));
    if (ready < 0 && errno != EINTR)
      throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
    if (ready > 0) {
      if (const auto signal = stop.take(); !signal.empty()) {
        reason = signal;
        break;
      }
    }
    on_refresh();
    if (duration && std::chrono::steady_clock::now() - started >= *duration) break;
  }
  if (!quiet) fmt::print(stderr, "m2mlat: collect: stopping ({})\n", reason);
  coordinator.stop();
  // The final numbers, from everything the agents held (those of `m2mlat stats` on the campaign).
  view.finish(coordinator.health(), core::now_ns(CLOCK_REALTIME));
  print_summary(coordinator.health(), c.store_path, c.json);
  return 0;
}

}  // namespace

Runner attach_collect(CLI::App& sub) {
  auto c = std::make_shared<CollectCommand>();
  sub.add_option("--agent", c->agents, "An agent's URL, http(s)://HOST:PORT (repeat for each board)")
      ->required();
  sub.add_option("--store", c->store_path, "The campaign store (created if missing)")->required();
  sub.add_flag("--start-session", c->start_session, "Begin a new session on every agent at start");
  sub.add_option("--label", c->label, "Label of the sessions begun with --start-session");
  sub.add_option("--scenario", c->scenario, "Scenario of the sessions begun with --start-session");
  sub.add_flag("--stop-session", c->stop_session, "Stop the agents' sessions at the end");
  sub.add_option("--duration", c->duration,
                 "Stop after this long (e.g. 10min); default: until SIGINT/SIGTERM");
  sub.add_flag("--once", c->once, "Take what every agent holds now, then exit");
  sub.add_option("--stale-after", c->stale_after, "An agent silent for longer is reported stale")
      ->capture_default_str();
  sub.add_option("--refresh", c->refresh, "How often health (and the live views) are refreshed")
      ->capture_default_str();
  sub.add_option("--token-file", c->token_file, "File holding the agents' bearer token (else $M2MLAT_TOKEN)");
  sub.add_option("--ca-file", c->ca_file, "PEM file of the CAs trusted for https:// agents");
  sub.add_option("--connect-timeout", c->connect_timeout, "Connection timeout")->capture_default_str();
  sub.add_option("--read-timeout", c->read_timeout, "Longest silence of an agent before the link is dropped")
      ->capture_default_str();
  sub.add_option("--poll", c->poll,
                 "Poll /v1/events at this interval instead of following the stream (0 = stream)")
      ->capture_default_str();
  sub.add_option("--durability", c->durability, "full, normal or off (docs/store.md)")->capture_default_str();
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  sub.add_flag("--quiet", c->quiet, "Print only errors and unhealthy agents");
  // --token-file above is the dashboard's token too.
  c->live.add_to(sub, false);
  return [c] { return run_collect(*c); };
}

}  // namespace m2mlat::cli
