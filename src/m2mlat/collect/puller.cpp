// The puller's loop: catch up by pages, follow the stream, back off and resume from the cursor.
#include "m2mlat/collect/puller.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <future>

#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/net/wire.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::collect {

namespace {

// How many of `events` lie beyond `cursor` (the store skips the others).
std::size_t beyond(const std::vector<store::StoredEvent>& events, std::int64_t cursor) {
  return static_cast<std::size_t>(std::count_if(events.begin(), events.end(),
                                                [&](const store::StoredEvent& e) { return e.seq > cursor; }));
}

}  // namespace

Puller::Puller(PullerOptions options, std::shared_ptr<NodeTracker> tracker, ErrorSink on_error)
    : options_(std::move(options)),
      tracker_(std::move(tracker)),
      on_error_(std::move(on_error)),
      control_(options_.url, options_.client),
      stream_(options_.url, options_.client) {
  if (options_.page < 1 || options_.page > 10000)
    throw core::Error(core::ErrorKind::usage, fmt::format("page size {} out of 1..10000", options_.page));
}

Puller::~Puller() { stop(false); }

void Puller::start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] { run(); });
}

void Puller::stop(bool drain) {
  {
    std::lock_guard lock(mutex_);
    drain_ = drain;
    stop_ = true;
  }
  wake_.notify_all();
  stream_.cancel();
  if (thread_.joinable()) thread_.join();
}

void Puller::end_run() {
  std::lock_guard lock(rejoin_mutex_);
  run_ended_ = true;
}

bool Puller::wait(std::chrono::milliseconds d) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, d, [this] { return stop_.load(); });
  return !stop_;
}

void Puller::run() {
  auto backoff = options_.backoff_min;
  std::optional<store::Store> store;
  while (!stopping()) {
    try {
      if (!store) {
        store::Options so;
        so.durability = options_.durability;
        so.create = false;
        store = store::Store::open(options_.store_path, so);
      }
      pull(*store);
    } catch (const std::exception& e) {
      if (stopping()) break;
      tracker_->failed(e.what(), core::now_ns(CLOCK_REALTIME));
      if (on_error_) on_error_(control_.url(), e.what());
      if (!wait(backoff)) break;
      backoff = std::min(backoff * 2, options_.backoff_max);
      continue;
    }
    backoff = options_.backoff_min;
  }
  bool drain = false;
  {
    std::lock_guard lock(mutex_);
    drain = drain_;
  }
  if (drain && store) {
    draining_ = true;  // catch_up goes on to the end despite the stop
    try {
      note_status(control_.status());
      sync_sessions();
      catch_up(*store);
    } catch (const std::exception& e) {
      tracker_->failed(e.what(), core::now_ns(CLOCK_REALTIME));
      if (on_error_) on_error_(control_.url(), fmt::format("final pull: {}", e.what()));
    }
  }
}

void Puller::catch_up_once() {
  store::Options so;
  so.durability = options_.durability;
  so.create = false;
  auto store = store::Store::open(options_.store_path, so);
  note_status(control_.status());
  sync_sessions();
  catch_up(store);
}

void Puller::note_status(const net::Status& status) {
  if (status.store_id.empty())
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}/v1/status: field 'store_id': empty", control_.url()));
  if (status.store_id != origin_) {  // a first contact, or the agent now has another store
    origin_ = status.store_id;
    sessions_.clear();
    unsent_.clear();
    open_session_.reset();
  }
  std::optional<ClockState> clock;
  if (status.clock)
    clock = ClockState{status.clock->offset_ns, status.clock->max_error_ns, status.clock->synchronised};
  tracker_->status(status.node, status.role, status.lost, status.last_seq, clock, core::now_ns(CLOCK_REALTIME));
  std::optional<std::int64_t> open =
      status.session ? std::optional<std::int64_t>(status.session->id) : std::nullopt;
  std::unique_lock rejoin(rejoin_mutex_);
  if (const auto& run = options_.run_session; run && !run_ended_ && !stopping() && !draining_ &&
                                              (!status.session || status.session->label != run->first ||
                                               status.session->scenario != run->second)) {
    // The agent restarted (or another client changed its session): it rejoins the run.
    const auto rejoined = control_.start_session(run->first, run->second);
    open = rejoined.id;
    if (on_error_)
      on_error_(control_.url(), fmt::format("{}: its session {} is not the run's: rejoined the run as session {} "
                                            "(scenario '{}', label '{}')",
                                            control_.url(),
                                            status.session ? std::to_string(status.session->id) : "none",
                                            rejoined.id, run->second, run->first));
    sync_sessions();
  }
  // The open session changed (started, stopped or replaced): the sessions' ends changed too.
  if (open != open_session_ && !sessions_.empty()) sync_sessions();
  open_session_ = open;
}

void Puller::sync_sessions() {
  for (auto& session : control_.sessions()) {
    const auto it = sessions_.find(session.id);
    if (it != sessions_.end() && it->second == session) continue;
    unsent_.insert(session.id);
    sessions_[session.id] = std::move(session);
  }
}

const store::Session* Puller::lookup(std::int64_t session_id) {
  auto it = sessions_.find(session_id);
  if (it == sessions_.end()) {  // begun after the last look: read them again, once
    sync_sessions();
    it = sessions_.find(session_id);
  }
  return it == sessions_.end() ? nullptr : &it->second;
}

void Puller::ingest(store::Store& store, std::vector<store::StoredEvent> events,
                    std::vector<store::StoredClockSample> samples, std::vector<store::StoredLoss> losses,
                    std::vector<store::StoredRateBlock> blocks, std::vector<store::StoredMarker> markers) {
  if (events.empty() && samples.empty() && losses.empty() && blocks.empty() && markers.empty() &&
      unsent_.empty())
    return;
  store::IngestBatch batch;
  batch.origin = origin_;
  // The sessions the items name (a cheap guarantee that the store knows them) and those changed.
  // The named ones are looked up first: one begun since the last look reads the agent's sessions
  // again, which can change others too (the previous session's end), and those must go in this
  // batch: unsent_ is cleared after it.
  std::set<std::int64_t> named;
  for (const auto& e : events) named.insert(e.session_id);
  for (const auto& s : samples) named.insert(s.sample.session_id);
  for (const auto& l : losses) named.insert(l.loss.session_id);
  for (const auto& b : blocks) named.insert(b.block.session_id);
  for (const auto& m : markers) named.insert(m.marker.session_id);
  for (auto id : named) {
    if (lookup(id) == nullptr)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: session {} is named but not in /v1/sessions", control_.url(), id));
  }
  named.insert(unsent_.begin(), unsent_.end());
  for (auto id : named) batch.sessions.push_back(sessions_.at(id));
  const auto new_events = beyond(events, cursor_.events);
  batch.events = std::move(events);
  batch.clock_samples = std::move(samples);
  batch.losses = std::move(losses);
  batch.rate_blocks = std::move(blocks);
  batch.markers = std::move(markers);
  cursor_ = store.ingest(batch);
  unsent_.clear();
  tracker_->stored(new_events, cursor_.events, core::now_ns(CLOCK_REALTIME));
}

void Puller::catch_up(store::Store& store) {
  cursor_ = store.ingest_cursor(origin_);
  tracker_->cursor(cursor_.events);
  const auto look = [this](std::int64_t id) { return lookup(id); };
  const auto halted = [this] { return stopping() && !draining_; };
  // Pipelined: while one page is decoded and stored, the next is already being fetched (on the
  // stream's client, idle meanwhile), from the seq on the page's last line.
  if (!halted()) {
    auto raw = control_.fetch_events(cursor_.events, options_.page);
    for (;;) {
      tracker_->contact(core::now_ns(CLOCK_REALTIME));
      std::future<net::RawEventPage> next;
      const auto last = raw.lines() == options_.page ? raw.last_event_seq() : std::nullopt;
      if (last && !halted())
        next = std::async(std::launch::async,
                          [this, after = *last] { return stream_.fetch_events(after, options_.page); });
      auto page = control_.decode_events(raw, look);
      ingest(store, std::move(page.events), {}, {});
      if (!next.valid()) break;
      raw = next.get();
    }
  }
  while (!halted()) {
    auto samples = control_.clock_samples_after(cursor_.clock_samples, options_.page);
    const bool full = samples.size() == options_.page;
    ingest(store, {}, std::move(samples), {});
    if (!full) break;
  }
  while (!halted()) {
    auto losses = control_.losses_after(cursor_.losses, options_.page);
    const bool full = losses.size() == options_.page;
    ingest(store, {}, {}, std::move(losses));
    if (!full) break;
  }
  if (!halted()) take_rate_blocks(store);
  if (!halted()) take_markers(store);
  ingest(store, {}, {}, {});  // sessions whose end became known
}

void Puller::take_rate_blocks(store::Store& store) {
  const auto page = std::min(options_.page, net::kMaxRateBlocksPerPage);
  while (!stopping() || draining_) {
    auto blocks = control_.rate_blocks_after(cursor_.rate_blocks, page);
    const bool full = blocks.size() == page;
    ingest(store, {}, {}, {}, std::move(blocks));
    if (!full) break;
  }
}

void Puller::take_markers(store::Store& store) {
  while (!stopping() || draining_) {
    auto markers = control_.markers_after(cursor_.markers, options_.page);
    const bool full = markers.size() == options_.page;
    ingest(store, {}, {}, {}, {}, std::move(markers));
    if (!full) break;
  }
}

void Puller::side_poll(store::Store& store) {
  note_status(control_.status());
  auto samples = control_.clock_samples_after(cursor_.clock_samples, options_.page);
  auto losses = control_.losses_after(cursor_.losses, options_.page);
  ingest(store, {}, std::move(samples), std::move(losses));
  take_rate_blocks(store);
  take_markers(store);
}

void Puller::pull(store::Store& store) {
  note_status(control_.status());
  sync_sessions();
  catch_up(store);

  auto last_side = std::chrono::steady_clock::now();
  const auto side_due = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_side < options_.side_interval) return false;
    last_side = now;
    return true;
  };

  if (options_.poll_interval.count() > 0) {
    while (wait(options_.poll_interval)) {
      if (side_due()) side_poll(store);
      catch_up(store);
    }
    return;
  }

  std::vector<store::StoredEvent> pending;
  const auto look = [this](std::int64_t id) { return lookup(id); };
  const auto on_event = [&](store::StoredEvent&& event) {
    pending.push_back(std::move(event));
    if (pending.size() >= options_.page) {
      ingest(store, std::move(pending), {}, {});
      pending.clear();
    }
    return !stopping();
  };
  const auto on_chunk = [&] {
    if (!pending.empty()) {
      ingest(store, std::move(pending), {}, {});
      pending.clear();
    }
    tracker_->contact(core::now_ns(CLOCK_REALTIME));
    if (side_due()) side_poll(store);
    return !stopping();
  };
  stream_.stream_events(cursor_.events, look, on_event, on_chunk);
  if (!pending.empty()) ingest(store, std::move(pending), {}, {});
}

}  // namespace m2mlat::collect
