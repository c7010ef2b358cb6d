// The live side of `m2mlat collect`: live pairing in its own thread, the terminal block and the
// web dashboard, fed by the coordinator's health snapshots.
//
// The coordinator calls refresh() every --refresh (250 ms): that only copies the health, draws the
// terminal block and publishes the dashboard's snapshot; it never waits for pairing. The pairing
// thread looks for new events in the store every `min_period` and re-pairs when there are, never
// more often than its own cost allows (after a re-pairing that took c it waits at least
// c / max_load), so a huge store slows the live numbers down instead of the coordinator; each new
// result is published to the dashboard at once (with the newest health refresh() gave). finish() pairs one
// last time, so the final numbers are those of `m2mlat stats` on the store.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "m2mlat/collect/dashboard.hpp"
#include "m2mlat/collect/health.hpp"
#include "m2mlat/collect/live_pairing.hpp"
#include "m2mlat/collect/terminal_view.hpp"

namespace m2mlat::collect {

struct LiveViewOptions {
  std::string store_path;                     // the campaign store (opened read-only)
  LiveOptions pairing;                        // channels, matcher and statistics options
  std::optional<DashboardOptions> dashboard;  // unset: no dashboard
  bool terminal = true;                       // draw the terminal block
  std::FILE* out = stdout;                    // where the block goes
  bool tty = false;                           // redraw in place (out is a terminal)
  std::chrono::nanoseconds plain_interval = std::chrono::seconds(5);  // plain block at most this often
  // Look for new events this often (a cheap query when there are none): the live numbers' delay.
  std::chrono::milliseconds min_period{50};
  double max_load = 0.25;  // share of one CPU re-pairing may take, (0, 1]
};

class LiveView {
 public:
  // Starts the pairing thread and, if asked, the dashboard (throws core::Error as Dashboard does).
  explicit LiveView(LiveViewOptions options);
  ~LiveView();  // stops everything (without the final pairing of finish())
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  // "http://127.0.0.1:8480/", or "" without a dashboard.
  std::string dashboard_url() const;

  // The newest health of every agent (CLOCK_REALTIME now_ns dates it); cheap, never blocks on pairing.
  void refresh(std::vector<NodeHealth> nodes, std::int64_t now_ns);
  // Stops the pairing thread, pairs the whole store once more, draws the final block and publishes
  // the final snapshot (the dashboard keeps serving it until destruction). Returns the final summary.
  LiveSummary finish(std::vector<NodeHealth> nodes, std::int64_t now_ns);

  // The latest pairing result (a copy).
  LiveSummary summary() const;

 private:
  void run();
  void stop_worker();

  LiveViewOptions options_;
  std::unique_ptr<LivePairing> pairing_;
  std::unique_ptr<Dashboard> dashboard_;
  std::unique_ptr<TerminalView> terminal_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  LiveSummary summary_;
  std::vector<NodeHealth> nodes_;  // from the last refresh(), for the worker's snapshots
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace m2mlat::collect
