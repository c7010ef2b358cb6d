// `m2mlat watch`: the live view of a store that another process is filling (a coordinator running
// elsewhere, or `m2mlat record` on a board that captures both wheels): the terminal block and,
// with --dashboard, the web dashboard, refreshed until SIGINT/SIGTERM or --duration; then the final
// numbers (those of `m2mlat stats` on the store).
#include <fmt/format.h>

#include <filesystem>
#include <poll.h>

#include <cerrno>
#include <cstring>
#include <memory>

#include "m2mlat/capture/stop_signal.hpp"
#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/live_flags.hpp"
#include "m2mlat/collect/health.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::cli {

namespace {

struct WatchCommand {
  std::string store_path;
  std::string duration, refresh = "250ms";
  LiveFlags live;
};

int run_watch(const WatchCommand& c) {
  const auto refresh =
      std::chrono::duration_cast<std::chrono::milliseconds>(core::parse_duration(c.refresh, 1'000'000));
  if (refresh.count() < 10) throw core::Error(core::ErrorKind::usage, "--refresh must be at least 10ms");
  std::optional<core::Duration> duration;
  if (!c.duration.empty()) duration = core::parse_duration(c.duration);
  if (!std::filesystem::exists(c.store_path))
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{}: no such store (watch reads a store that `record`, `agent` or `collect` "
                                  "writes: start it first)",
                                  c.store_path));
  auto options = c.live.options(c.store_path, "", true);

  capture::StopSignal stop;  // before any thread starts: they inherit the blocked signals
  collect::LiveView view(options);
  if (const auto url = view.dashboard_url(); !url.empty()) {
    fmt::print(stderr, "dashboard {}\n", url);
    std::fflush(stderr);
  }
  const auto started = std::chrono::steady_clock::now();
  for (;;) {
    pollfd fd{stop.fd(), POLLIN, 0};
    const int ready = ::poll(&fd, 1, static_cast<int>(refresh.count()));
    if (ready < 0 && errno != EINTR)
      throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
    if (ready > 0 && !stop.take().empty()) break;
    view.refresh({}, core::now_ns(CLOCK_REALTIME));
    if (duration && std::chrono::steady_clock::now() - started >= *duration) break;
  }
  const auto final_summary = view.finish({}, core::now_ns(CLOCK_REALTIME));
  return final_summary.state == collect::LiveState::error ? 65 : 0;
}

}  // namespace

Runner attach_watch(CLI::App& sub) {
  auto c = std::make_shared<WatchCommand>();
  sub.add_option("store", c->store_path, "The store to watch (it may not exist yet)")->required();
  sub.add_option("--duration", c->duration,
                 "Stop after this long (e.g. 10min); default: until SIGINT/SIGTERM");
  sub.add_option("--refresh", c->refresh, "How often the views are refreshed")->capture_default_str();
  c->live.add_to(sub);
  return [c] { return run_watch(*c); };
}

}  // namespace m2mlat::cli
