// The live side of `m2mlat collect`: the pairing thread and the views it feeds.
#include "m2mlat/collect/live_view.hpp"

#include <fmt/format.h>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::collect {

LiveView::LiveView(LiveViewOptions options) : options_(std::move(options)) {
  if (!(options_.max_load > 0 && options_.max_load <= 1))
    throw core::Error(core::ErrorKind::usage, "the live view's max_load must be in (0, 1]");
  pairing_ = std::make_unique<LivePairing>(options_.store_path, options_.pairing);
  summary_ = pairing_->current();
  if (options_.dashboard) {
    dashboard_ = std::make_unique<Dashboard>(*options_.dashboard);
    // A whole snapshot from the first request on (what the store holds already; no node seen yet).
    dashboard_->publish(snapshot_json(summary_, {}, core::now_ns(CLOCK_REALTIME)));
  }
  if (options_.terminal)
    terminal_ = std::make_unique<TerminalView>(options_.out, options_.tty, options_.plain_interval);
  worker_ = std::thread([this] { run(); });
}

LiveView::~LiveView() {
  stop_worker();
  if (dashboard_) dashboard_->stop();
}

std::string LiveView::dashboard_url() const { return dashboard_ ? dashboard_->url() : std::string(); }

void LiveView::run() {
  using Clock = std::chrono::steady_clock;
  auto due = Clock::now();
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_until(lock, due, [&] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    const auto started = Clock::now();
    const auto before = pairing_->current().pairings;
    auto result = pairing_->update();  // a copy, so the lock below is short
    const auto cost = Clock::now() - started;
    // Wait at least min_period, and long enough that re-pairing uses at most max_load of a CPU.
    auto wait = std::chrono::duration_cast<Clock::duration>(options_.min_period);
    if (result.pairings != before) {
      const auto paced = std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(std::chrono::duration<double>(cost).count() / options_.max_load));
      wait = std::max(wait, paced);
    }
    due = started + wait;
    const bool fresh = result.pairings != before;
    lock.lock();
    summary_ = std::move(result);
    // A new result goes to the dashboard at once, not at the next refresh(): the delay from an
    // effect event's commit to its sample on the page is then the store's poll plus the pairing.
    if (fresh && dashboard_) dashboard_->publish(snapshot_json(summary_, nodes_, core::now_ns(CLOCK_REALTIME)));
  }
}

void LiveView::stop_worker() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void LiveView::refresh(std::vector<NodeHealth> nodes, std::int64_t now_ns) {
  LiveSummary summary;
  {
    std::lock_guard lock(mutex_);
    summary = summary_;
    nodes_ = nodes;
  }
  if (dashboard_) dashboard_->publish(snapshot_json(summary, nodes, now_ns));
  if (terminal_) terminal_->show(summary, nodes, now_ns);
}

LiveSummary LiveView::finish(std::vector<NodeHealth> nodes, std::int64_t now_ns) {
  stop_worker();
  // The worker has ended: this thread may use the pairing (and its store) now.
  auto final_summary = pairing_->finish();
  {
    std::lock_guard lock(mutex_);
    summary_ = final_summary;
  }
  if (dashboard_) dashboard_->publish(snapshot_json(final_summary, nodes, now_ns));
  if (terminal_) terminal_->finish(final_summary, nodes, now_ns);
  return final_summary;
}

LiveSummary LiveView::summary() const {
  std::lock_guard lock(mutex_);
  return summary_;
}

}  // namespace m2mlat::collect
