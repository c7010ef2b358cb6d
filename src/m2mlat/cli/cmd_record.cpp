// `m2mlat record`: one node's recorder. Reads edges from a capture source (the GPIO character
// device, the reference module's kernel log, or the simulated rig), filters bounces, and writes
// events and losses durably into the store until SIGINT/SIGTERM, a count or a duration; then prints
// a summary per channel (events, suppressed bounces, losses). With --gyro, a gyroscope's raw samples
// are stored beside (all or a window around each motion; capture/gyro_channel.hpp). The options are
// shared with `m2mlat agent` (record_setup.hpp).
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/cli/record_setup.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

// Edge -> durable commit latency of the stored events (kernel timestamps on CLOCK_REALTIME, not
// simulated ones), ns; quantiles are bucket ends, at most 3 % above the true value.
nlohmann::json commit_latency_json(const capture::LatencyHistogram& h) {
  return {{"events", h.count()}, {"p50", h.quantile(0.5)}, {"p99", h.quantile(0.99)}, {"max", h.max()}};
}

nlohmann::json gyro_json(const GyroSetup& gyro) {
  const auto& g = gyro.channel->counters();
  const auto summary = gyro.source->summary();
  return {{"channel", gyro.channel->channel()}, {"read", g.read},
          {"stored", g.stored},                 {"left_out", g.left_out},
          {"outside_session", g.outside_session},
          {"missed_periods", g.missed_periods}, {"i2c_errors", g.i2c_errors},
          {"stop_reason", summary.stop_reason}, {"error", summary.error}};
}

int run_record(RecordFlags& c) {
  // First, before the line is requested and the store opened: a SIGINT or SIGTERM during a slow
  // start (a busy board) then stops the run at its first poll, with every edge already queued read,
  // instead of ending the process with the signal's status. Before any thread starts (the
  // gyroscope's), so that every thread blocks the signals.
  capture::StopSignal stop;
  auto setup = prepare_record(c);
  const auto& node = setup.node;
  const auto role = setup.role;
  const auto& source_kind = setup.source_kind;
  auto& source = setup.source;
  if (!c.quiet)
    for (const auto& line : source->describe()) fmt::print(stderr, "m2mlat: {}\n", core::printable(line));
  auto options = setup.options;
  if (!c.quiet && stderr_is_terminal()) options.on_progress = print_counters;

  auto store = store::Store::open(c.store_path, setup.store_options);
  apply_rt(setup, c.quiet);
  if (setup.gyro) setup.gyro->start();
  capture::Recorder recorder(store, *source, options);
  const auto counters = recorder.run(stop.fd(), [&] { return stop.take(); });
  progress_done();
  warn_after_run(setup);

  if (c.json) {
    nlohmann::json j{{"store", c.store_path},
                     {"session", counters.session_id},
                     {"node", node},
                     {"role", core::to_string(role)},
                     {"source", source_kind},
                     {"stop_reason", counters.stop_reason},
                     {"events", counters.events},
                     {"node_losses", counters.node_lost},
                     {"last_committed_seq", counters.last_committed_seq},
                     {"cut_sessions", counters.cut_sessions},
                     {"commit_latency_ns", commit_latency_json(counters.commit_latency)},
                     {"commit_latency_replayed", counters.commit_latency_replayed},
                     {"channels", nlohmann::json::array()}};
    for (const auto& ch : counters.channels) {
      nlohmann::json row{
          {"channel", ch.channel}, {"events", ch.events}, {"suppressed", ch.suppressed}, {"losses", ch.lost}};
      row["last_ns"] = ch.last ? nlohmann::json(ch.last->ns()) : nlohmann::json(nullptr);
      j["channels"].push_back(row);
    }
    if (setup.gyro) j["gyro"] = gyro_json(*setup.gyro);
    print_json(j);
  } else {
    fmt::print("{}: session {} of node {} ({}), {} events, stopped by {}\n", core::printable(c.store_path),
               counters.session_id, core::printable(node), core::to_string(role), counters.events,
               counters.stop_reason);
    fmt::print("  {:<16} {:>10} {:>10} {:>8}  {}\n", "channel", "events", "suppressed", "losses",
               "last timestamp");
    for (const auto& ch : counters.channels)
      fmt::print("  {:<16} {:>10} {:>10} {:>8}  {}\n", core::printable(ch.channel), ch.events, ch.suppressed,
                 ch.lost, ch.last ? core::format_seconds(ch.last->ns()) : "-");
    if (!counters.cut_sessions.empty())
      fmt::print("  closed session(s) {} of node {}, cut by a crash: each has a 'restart' loss\n",
                 fmt::join(counters.cut_sessions, ", "), core::printable(node));
    if (setup.gyro) {
      const auto& g = setup.gyro->channel->counters();
      const auto summary = setup.gyro->source->summary();
      fmt::print("  gyroscope {}: {} samples read, {} stored, {} outside the keep window, {} before the session "
                 "began, {} missed periods, {} I2C errors{}\n",
                 core::printable(setup.gyro->channel->channel()), g.read, g.stored, g.left_out,
                 g.outside_session, g.missed_periods,
                 g.i2c_errors, summary.error.empty() ? "" : " (" + core::printable(summary.error) + ")");
    }
    if (counters.node_lost > 0) fmt::print("  {} kernel-log records lost (node-wide)\n", counters.node_lost);
    if (const auto& h = counters.commit_latency; h.count() > 0)
      fmt::print("  edge -> durable commit: p50 {}, p99 {}, max {} ({} events)\n",
                 core::format_duration(core::Duration{h.quantile(0.5)}),
                 core::format_duration(core::Duration{h.quantile(0.99)}),
                 core::format_duration(core::Duration{h.max()}), h.count());
    if (counters.commit_latency_replayed > 0)
      fmt::print(
          "  edge -> durable commit: n/a for {} replayed events (stamped before the recording began)\n",
          counters.commit_latency_replayed);
  }
  return 0;
}

}  // namespace

Runner attach_record(CLI::App& sub) {
  auto c = std::make_shared<RecordFlags>();
  add_record_options(sub, *c);
  sub.add_flag("--json", c->json, "Print the summary as JSON");
  return [c] { return run_record(*c); };
}

}  // namespace m2mlat::cli
