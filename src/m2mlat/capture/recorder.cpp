// The writing side: poll(2) on the reading queue and the stop descriptor; gates, writer, losses,
// limits, commit rounds, final drain.
#include "m2mlat/capture/recorder.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

#include "m2mlat/capture/source_reader.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/event_writer.hpp"

namespace m2mlat::capture {

core::TimePoint realtime_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return core::TimePoint::from_ns(core::Clock::realtime,
                                  std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec);
}

core::Duration monotonic_now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return core::Duration{std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec};
}

Recorder::Recorder(store::Store& store, Source& source, RecorderOptions options)
    : store_(store), source_(source), options_(std::move(options)) {
  for (const auto& name : source_.channels()) channel(name);
}

Recorder::Channel& Recorder::channel(const std::string& name) {
  const auto it = index_.find(name);
  if (it != index_.end()) return channels_[it->second];
  const auto period = options_.refractory.find(name);
  channels_.push_back(
      {{name, 0, 0, 0, std::nullopt},
       RefractoryGate(period == options_.refractory.end() ? core::Duration{0} : period->second)});
  index_.emplace(name, channels_.size() - 1);
  return channels_.back();
}

Recorder::Channel& Recorder::channel_of(const core::Event& event) {
  // Nearly every event is on the channel of the one before: no map lookup for those.
  if (last_channel_ < channels_.size() && channels_[last_channel_].counters.channel == event.channel)
    return channels_[last_channel_];
  auto& c = channel(event.channel);
  last_channel_ = static_cast<std::size_t>(&c - channels_.data());
  return c;
}

std::int64_t Recorder::begin(const store::Session& session) {
  auto copy = session;
  copy.start = realtime_now();
  copy.end.reset();
  return store_.begin_session(copy);
}

RecordCounters Recorder::run(int stop_fd, const std::function<std::string()>& stop_name) {
  RecordCounters counters;
  store::WriterOptions writer_options;
  writer_options.max_batch = std::max<std::size_t>(options_.batch, 1);
  writer_options.max_age = options_.commit_interval;
  writer_options.age_on_add = false;  // the rounds below keep the time
  writer_options.on_commit = [&counters](const store::Batch& committed, const store::AppendResult&) {
    const auto now = realtime_now().ns();
    // Only edges this machine's kernel timestamped: a simulated rig's times are on its own clocks.
    for (const auto& event : committed.events)
      if (event.time.clock() == core::Clock::realtime && (event.flags & core::kFlagSimulated) == 0)
        counters.commit_latency.add(now - event.time.ns());
  };
  // The writer of the open session; empty while none is open (agent only).
  std::optional<store::EventWriter> writer;
  SessionControl* const control = options_.control;
  // Before this node's first session: a session of it still open was cut by a crash; end it and
  // record the cut, so that neither stays open for ever nor hides the gap.
  for (const auto& cut : store_.close_cut_sessions(options_.session.node, realtime_now()))
    counters.cut_sessions.push_back(cut.id);
  if (options_.start_session || control == nullptr) {
    counters.session_id = begin(options_.session);
    writer.emplace(store_, counters.session_id, writer_options);
  }
  std::int64_t last_committed = store_.last_seq();
  std::int64_t ended_session = counters.session_id;  // reported once run() returns

  const auto started = monotonic_now();
  auto last_progress = started;
  const auto snapshot = [&] {
    counters.channels.clear();
    for (const auto& c : channels_) {
      auto copy = c.counters;
      copy.suppressed = c.gate.suppressed();
      counters.channels.push_back(copy);
    }
    if (writer) last_committed = std::max(last_committed, writer->last_committed_seq());
    counters.last_committed_seq = last_committed;
  };
  const auto report_progress = [&] {
    last_progress = monotonic_now();
    snapshot();
    if (options_.on_progress) options_.on_progress(counters);
  };
  // Commits the open session's batch and ends it; returns it as stored.
  const auto end_open = [&]() -> std::optional<store::Session> {
    if (!writer) return std::nullopt;
    writer->flush();
    last_committed = std::max(last_committed, writer->last_committed_seq());
    writer.reset();
    store_.end_session(counters.session_id, realtime_now());
    ended_session = counters.session_id;
    auto ended = store_.session(counters.session_id);
    counters.session_id = 0;
    return ended;
  };
  const auto clock_samples = [&] {
    if (!writer || !options_.before_commit) return;
    std::vector<store::ClockSample> samples;
    options_.before_commit(counters.session_id, samples);
    for (const auto& sample : samples) writer->add(sample);
  };

  const auto serve_requests = [&] {
    while (auto request = control->next()) {
      SessionControl::Outcome outcome;
      outcome.ended = end_open();
      if (request->begin) {
        counters.session_id = begin(*request->begin);
        writer.emplace(store_, counters.session_id, writer_options);
        outcome.begun = store_.session(counters.session_id);
      }
      control->complete(request->ticket, std::move(outcome));
      report_progress();
    }
  };

  bool limit_reached = false;
  bool finished = false;
  const auto take = [&](ReadResult& batch) {
    finished = finished || batch.finished;
    if (!writer) {
      // No session: nothing can be stored (a loss needs a session too); count what passes by.
      counters.dropped += batch.events.size();
      return;
    }
    for (auto& sample : batch.clock_samples) {
      sample.session_id = counters.session_id;
      writer->add(sample);
    }
    if (!batch.gaps.empty()) {
      const auto detected = realtime_now();
      for (const auto& gap : batch.gaps) {
        store::Loss loss{counters.session_id, gap.channel, detected, gap.first_missing, gap.count, gap.kind};
        writer->add(loss);
        if (gap.channel.empty())
          counters.node_lost += gap.count;
        else
          channel(gap.channel).counters.lost += gap.count;
      }
    }
    for (const auto& event : batch.events) {
      if (limit_reached) break;
      auto& c = channel_of(event);
      if (!c.gate.admit(event.time)) continue;
      writer->add(event);
      ++c.counters.events;
      c.counters.last = event.time;
      ++counters.events;
      if (options_.max_events > 0 && counters.events >= options_.max_events) limit_reached = true;
    }
  };
  const auto notify_commit = [&] {
    if (!writer) return;
    const auto seq = writer->last_committed_seq();
    if (seq > last_committed) {
      last_committed = seq;
      if (options_.on_commit) options_.on_commit(seq);
    }
  };

  SourceReaderOptions reader_options = options_.reader;
  reader_options.chunk_events = std::max<std::size_t>(reader_options.chunk_events, 1);
  reader_options.wake_events = writer_options.max_batch;
  std::vector<std::unique_ptr<ReadResult>> chunks;
  std::optional<SourceReader> reader;
  // One round: everything queued is taken, gated and committed (in batches of at most max_batch, the
  // rest at the end): each event is counted as stored only once its commit has returned.
  auto last_round = monotonic_now();
  const auto commit_round = [&] {
    last_round = monotonic_now();
    reader->take(chunks);
    for (auto& chunk : chunks) {
      take(*chunk);
      if (limit_reached) break;
    }
    reader->give_back(chunks);
    clock_samples();
    if (writer) writer->flush();
    notify_commit();
  };
  // Rethrows the reading thread's failure once what it read before is committed.
  const auto check_reader = [&] {
    if (const auto error = reader->error()) std::rethrow_exception(error);
  };

  try {
    reader.emplace(source_, reader_options);
    const LeaveRealtimeToReader leave_realtime;
    for (;;) {
      const auto now = monotonic_now();
      const auto queued = reader->status();
      // When the queue's oldest event has waited the commit interval, or a batch is full: a round.
      // Without events too, a round every commit interval gives the clock monitor its turn (it
      // stores a sample when one is due, and its state even while no edge comes).
      const bool monitor_due =
          writer && options_.before_commit && now - last_round >= options_.commit_interval;
      if (queued.ended || queued.events >= writer_options.max_batch || monitor_due ||
          (queued.first && now - *queued.first >= options_.commit_interval)) {
        commit_round();
        check_reader();
        if (limit_reached) {
          counters.stop_reason = "count";
          break;
        }
        if (finished) {
          counters.stop_reason = "source finished";
          break;
        }
        if (queued.ended) {  // stopped from outside the loop: cannot happen, but never spin
          counters.stop_reason = "stop";
          break;
        }
      }
      if (options_.on_progress && now - last_progress >= options_.progress_interval) report_progress();

      auto timeout = options_.progress_interval - (now - last_progress);
      if (!options_.on_progress) timeout = std::chrono::hours(1);
      if (writer && options_.before_commit)
        timeout = std::min(timeout, last_round + options_.commit_interval - now);
      if (const auto first = reader->status().first)
        timeout = std::min(timeout, *first + options_.commit_interval - now);
      if (options_.max_duration.count() > 0) {
        const auto left = options_.max_duration - (now - started);
        if (left.count() <= 0) {
          counters.stop_reason = "duration";
          break;
        }
        timeout = std::min(timeout, left);
      }
      pollfd fds[3] = {
          {stop_fd, POLLIN, 0}, {reader->fd(), POLLIN, 0}, {control ? control->fd() : -1, POLLIN, 0}};
      const int timeout_ms =
          static_cast<int>(std::max<std::int64_t>(0, (timeout.count() + 999'999) / 1'000'000));
      if (::poll(fds, 3, timeout_ms) < 0 && errno != EINTR)
        throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
      if ((fds[1].revents & POLLIN) != 0) reader->clear_wake();
      if (stop_fd >= 0 && (fds[0].revents & POLLIN) != 0) {
        counters.stop_reason = stop_name ? stop_name() : "stop";
        if (counters.stop_reason.empty()) counters.stop_reason = "stop";
        break;
      }
      if (control != nullptr && (fds[2].revents & POLLIN) != 0) {
        // What was read before the request belongs to the session it may end.
        commit_round();
        serve_requests();
      }
    }

    // What the kernel buffered before the stop was acknowledged by nobody yet: keep it too. The
    // reader reads until the source is empty, and every round commits what it handed over.
    reader->stop(!limit_reached);
    while (!limit_reached) {
      const bool ended = reader->status().ended;
      commit_round();
      if (ended) break;
      pollfd fd{reader->fd(), POLLIN, 0};
      ::poll(&fd, 1, 100);
      reader->clear_wake();
    }
    check_reader();
    clock_samples();
  } catch (...) {
    // A source that fails (a device gone, a read error): keep what was read and close the session,
    // then report the failure.
    if (control != nullptr) control->close();
    try {
      reader.reset();  // stopped and joined: nothing reads any more
      end_open();
    } catch (...) {  // NOLINT(bugprone-empty-catch): the first failure is the one to report
    }
    throw;
  }
  reader.reset();
  if (control != nullptr) control->close();
  end_open();
  counters.session_id = ended_session;
  snapshot();
  if (options_.on_commit) options_.on_commit(last_committed);
  if (options_.on_progress) options_.on_progress(counters);
  return counters;
}

}  // namespace m2mlat::capture
