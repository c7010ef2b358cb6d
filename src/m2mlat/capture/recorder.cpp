// The writing side: poll(2) on the reading queue and the stop descriptor; gates, writer, losses,
// limits, commit rounds, final drain. One run is a Recorder::Run, its steps named member functions.
#include "m2mlat/capture/recorder.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>

#include "m2mlat/capture/source_reader.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/store/event_writer.hpp"

namespace m2mlat::capture {

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
  copy.start = core::realtime_now();
  copy.end.reset();
  return store_.begin_session(copy);
}

// One call of run(): its state, and its steps as member functions in the order they happen:
// open the first session, record until a stop (commit rounds, session requests, progress), drain
// what the kernel still buffers, and finish (or, on a failure, abandon) the open session.
class Recorder::Run {
 public:
  Run(Recorder& recorder, int stop_fd, const std::function<std::string()>& stop_name);
  Run(const Run&) = delete;  // the writer's commit hook points at counters_
  Run& operator=(const Run&) = delete;
  RecordCounters execute();

 private:
  // Sessions.
  void open_first_session();
  void begin_session(const store::Session& session);
  std::optional<store::Session> end_open();
  void serve_requests();
  // A commit round and its parts.
  void commit_round();
  void take(ReadResult& batch);
  void add_gaps(const std::vector<Gap>& gaps);
  void add_events(const std::vector<core::Event>& events);
  void add_clock_samples(bool final = false);
  void add_raw_samples(bool final, std::optional<core::TimePoint> end);
  void notify_commit();
  void check_reader();
  // The loop, the drain and the end.
  void record_until_stop();
  bool round_due(core::Duration now, const SourceReader::Status& queued) const;
  bool stops_after_round(const SourceReader::Status& queued);
  std::optional<core::Duration> wait_timeout(core::Duration now);  // nullopt: the duration is up
  bool wait(core::Duration timeout);                               // true: stop_fd is readable
  void drain_after_stop();
  void abandon() noexcept;
  RecordCounters finish();
  // Progress.
  void snapshot();
  void report_progress();

  Recorder& recorder_;
  const RecorderOptions& options_;
  const int stop_fd_;
  const std::function<std::string()>& stop_name_;
  SessionControl* const control_;
  RecordCounters counters_;
  store::WriterOptions writer_options_;
  std::optional<store::EventWriter> writer_;  // the open session's; empty while none is open (agent)
  std::int64_t last_committed_ = 0;
  std::int64_t ended_session_ = 0;  // reported once run() returns
  core::TimePoint session_start_;   // the open session's start
  core::Duration started_{0}, last_progress_{0}, last_round_{0};
  // CLOCK_REALTIME when the run began, ns: edges stamped earlier are replayed ones
  std::int64_t started_realtime_ns_ = core::realtime_now().ns();
  bool limit_reached_ = false;
  bool finished_ = false;
  std::vector<std::unique_ptr<ReadResult>> chunks_;
  std::optional<SourceReader> reader_;
};

RecordCounters Recorder::run(int stop_fd, const std::function<std::string()>& stop_name) {
  Run run(*this, stop_fd, stop_name);
  return run.execute();
}

Recorder::Run::Run(Recorder& recorder, int stop_fd, const std::function<std::string()>& stop_name)
    : recorder_(recorder),
      options_(recorder.options_),
      stop_fd_(stop_fd),
      stop_name_(stop_name),
      control_(recorder.options_.control) {
  writer_options_.max_batch = std::max<std::size_t>(options_.batch, 1);
  writer_options_.max_age = options_.commit_interval;
  writer_options_.age_on_add = false;  // the rounds keep the time
  writer_options_.on_commit = [this](const store::Batch& committed, const store::AppendResult&) {
    const auto now = core::realtime_now().ns();
    // Only edges this machine's kernel timestamped: a simulated rig's times are on its own clocks.
    // An edge stamped before the run began was replayed (an old log), not recorded as it happened.
    for (const auto& event : committed.events) {
      if (event.time.clock() != core::Clock::realtime || (event.flags & core::kFlagSimulated) != 0) continue;
      if (event.time.ns() < started_realtime_ns_)
        ++counters_.commit_latency_replayed;
      else
        counters_.commit_latency.add(now - event.time.ns());
    }
  };
}

RecordCounters Recorder::Run::execute() {
  open_first_session();
  last_committed_ = recorder_.store_.last_seq();
  ended_session_ = counters_.session_id;
  started_ = core::monotonic_now();
  last_progress_ = started_;
  last_round_ = core::monotonic_now();
  try {
    SourceReaderOptions reader_options = options_.reader;
    reader_options.chunk_events = std::max<std::size_t>(reader_options.chunk_events, 1);
    reader_options.wake_events = writer_options_.max_batch;
    reader_.emplace(recorder_.source_, reader_options);
    const LeaveRealtimeToReader leave_realtime;
    record_until_stop();
    drain_after_stop();
    check_reader();
    add_clock_samples(true);
  } catch (...) {
    abandon();
    throw;
  }
  return finish();
}

// ---- sessions ----

void Recorder::Run::open_first_session() {
  // Before this node's first session: a session of it still open was cut by a crash; end it and
  // record the cut, so that neither stays open for ever nor hides the gap.
  for (const auto& cut : recorder_.store_.close_cut_sessions(options_.session.node, core::realtime_now()))
    counters_.cut_sessions.push_back(cut.id);
  if (options_.start_session || control_ == nullptr) begin_session(options_.session);
}

void Recorder::Run::begin_session(const store::Session& session) {
  counters_.session_id = recorder_.begin(session);
  session_start_ = recorder_.store_.session(counters_.session_id)->start;
  writer_.emplace(recorder_.store_, counters_.session_id, writer_options_);
}

// Commits the open session's batch and ends it; returns it as stored.
std::optional<store::Session> Recorder::Run::end_open() {
  if (!writer_) return std::nullopt;
  // The end is taken first: the raw samples stamped up to it are the session's, in its last commit.
  const auto end = core::realtime_now();
  add_raw_samples(false, end);
  writer_->flush();
  last_committed_ = std::max(last_committed_, writer_->last_committed_seq());
  writer_.reset();
  recorder_.store_.end_session(counters_.session_id, end);
  ended_session_ = counters_.session_id;
  auto ended = recorder_.store_.session(counters_.session_id);
  counters_.session_id = 0;
  return ended;
}

void Recorder::Run::serve_requests() {
  while (auto request = control_->next()) {
    SessionControl::Outcome outcome;
    outcome.ended = end_open();
    if (request->begin) {
      begin_session(*request->begin);
      outcome.begun = recorder_.store_.session(counters_.session_id);
    }
    control_->complete(request->ticket, std::move(outcome));
    report_progress();
  }
}

// ---- a commit round ----

// Everything queued is taken, gated and committed (in batches of at most max_batch, the rest at the
// end): each event is counted as stored only once its commit has returned.
void Recorder::Run::commit_round() {
  last_round_ = core::monotonic_now();
  reader_->take(chunks_);
  for (auto& chunk : chunks_) {
    take(*chunk);
    if (limit_reached_) break;
  }
  reader_->give_back(chunks_);
  add_clock_samples();
  if (writer_) writer_->flush();
  notify_commit();
}

void Recorder::Run::take(ReadResult& batch) {
  finished_ = finished_ || batch.finished;
  if (!writer_) {
    // No session: nothing can be stored (a loss needs a session too); count what passes by.
    counters_.dropped += batch.events.size();
    return;
  }
  for (auto& sample : batch.clock_samples) {
    sample.session_id = counters_.session_id;
    writer_->add(sample);
  }
  if (!batch.clock_samples.empty()) counters_.last_clock = batch.clock_samples.back();
  add_gaps(batch.gaps);
  add_events(batch.events);
}

void Recorder::Run::add_gaps(const std::vector<Gap>& gaps) {
  if (gaps.empty()) return;
  const auto detected = core::realtime_now();
  for (const auto& gap : gaps) {
    store::Loss loss{counters_.session_id, gap.channel, detected, gap.first_missing, gap.count, gap.kind};
    writer_->add(loss);
    if (gap.channel.empty())
      counters_.node_lost += gap.count;
    else
      recorder_.channel(gap.channel).counters.lost += gap.count;
  }
}

void Recorder::Run::add_events(const std::vector<core::Event>& events) {
  for (const auto& event : events) {
    if (limit_reached_) break;
    auto& c = recorder_.channel_of(event);
    if (!c.gate.admit(event.time)) continue;
    writer_->add(event);
    ++c.counters.events;
    c.counters.last = event.time;
    ++counters_.events;
    if (options_.max_events > 0 && counters_.events >= options_.max_events) limit_reached_ = true;
  }
}

// The clock monitor's samples and the raw rate samples for the open session, committed with the
// round; `final`: the last round, after the stop.
void Recorder::Run::add_clock_samples(bool final) {
  if (writer_ && options_.before_commit) {
    std::vector<store::ClockSample> samples;
    options_.before_commit(counters_.session_id, samples);
    for (const auto& sample : samples) writer_->add(sample);
    if (!samples.empty()) counters_.last_clock = samples.back();
  }
  add_raw_samples(final, std::nullopt);
}

// The raw-sample hook's round for the open session (none: what it sampled is let go), up to `end`
// when the session ends.
void Recorder::Run::add_raw_samples(bool final, std::optional<core::TimePoint> end) {
  if (!options_.raw_samples) return;
  RawRound round;
  round.final = final;
  round.end = end;
  if (writer_) {
    round.session_id = counters_.session_id;
    round.session_start = session_start_;
  }
  std::vector<store::RateBlock> blocks;
  std::vector<store::Loss> losses;
  options_.raw_samples(round, blocks, losses);
  if (!writer_) return;
  for (const auto& block : blocks) writer_->add(block);
  for (const auto& loss : losses) writer_->add(loss);
}

void Recorder::Run::notify_commit() {
  if (!writer_) return;
  const auto seq = writer_->last_committed_seq();
  if (seq > last_committed_) {
    last_committed_ = seq;
    if (options_.on_commit) options_.on_commit(seq);
  }
}

// Rethrows the reading thread's failure once what it read before is committed.
void Recorder::Run::check_reader() {
  if (const auto error = reader_->error()) std::rethrow_exception(error);
}

// ---- the loop, the drain and the end ----

void Recorder::Run::record_until_stop() {
  for (;;) {
    const auto now = core::monotonic_now();
    const auto queued = reader_->status();
    if (round_due(now, queued)) {
      commit_round();
      check_reader();
      if (stops_after_round(queued)) return;
    }
    if (options_.on_progress && now - last_progress_ >= options_.progress_interval) report_progress();
    const auto timeout = wait_timeout(now);
    if (!timeout) {
      counters_.stop_reason = "duration";
      return;
    }
    if (wait(*timeout)) {
      counters_.stop_reason = stop_name_ ? stop_name_() : "stop";
      if (counters_.stop_reason.empty()) counters_.stop_reason = "stop";
      return;
    }
  }
}

// When the queue's oldest event has waited the commit interval, or a batch is full: a round.
// Without events too, a round every commit interval gives the clock monitor its turn (it stores a
// sample when one is due, and its state even while no edge comes).
bool Recorder::Run::round_due(core::Duration now, const SourceReader::Status& queued) const {
  const bool monitor_due = (options_.raw_samples || (writer_ && options_.before_commit)) &&
                           now - last_round_ >= options_.commit_interval;
  return queued.ended || queued.events >= writer_options_.max_batch || monitor_due ||
         (queued.first && now - *queued.first >= options_.commit_interval);
}

// After a round: a limit reached, the source finished or the reader ended set the stop reason.
bool Recorder::Run::stops_after_round(const SourceReader::Status& queued) {
  if (limit_reached_)
    counters_.stop_reason = "count";
  else if (finished_)
    counters_.stop_reason = "source finished";
  else if (queued.ended)  // stopped from outside the loop: cannot happen, but never spin
    counters_.stop_reason = "stop";
  else
    return false;
  return true;
}

// How long to wait for the next thing to do: progress, the clock monitor's round, the oldest queued
// event's commit, the duration limit.
std::optional<core::Duration> Recorder::Run::wait_timeout(core::Duration now) {
  auto timeout = options_.progress_interval - (now - last_progress_);
  if (!options_.on_progress) timeout = std::chrono::hours(1);
  if (options_.raw_samples || (writer_ && options_.before_commit))
    timeout = std::min(timeout, last_round_ + options_.commit_interval - now);
  if (const auto first = reader_->status().first)
    timeout = std::min(timeout, *first + options_.commit_interval - now);
  if (options_.max_duration.count() > 0) {
    const auto left = options_.max_duration - (now - started_);
    if (left.count() <= 0) return std::nullopt;
    timeout = std::min(timeout, left);
  }
  return timeout;
}

// Waits on the stop descriptor, the reader and the session control; serves session requests.
bool Recorder::Run::wait(core::Duration timeout) {
  pollfd fds[3] = {
      {stop_fd_, POLLIN, 0}, {reader_->fd(), POLLIN, 0}, {control_ ? control_->fd() : -1, POLLIN, 0}};
  const int timeout_ms = static_cast<int>(std::max<std::int64_t>(0, (timeout.count() + 999'999) / 1'000'000));
  if (::poll(fds, 3, timeout_ms) < 0 && errno != EINTR)
    throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
  if ((fds[1].revents & POLLIN) != 0) reader_->clear_wake();
  if (stop_fd_ >= 0 && (fds[0].revents & POLLIN) != 0) return true;
  if (control_ != nullptr && (fds[2].revents & POLLIN) != 0) {
    // What was read before the request belongs to the session it may end.
    commit_round();
    serve_requests();
  }
  return false;
}

// What the kernel buffered before the stop was acknowledged by nobody yet: keep it too. The reader
// reads until the source is empty, and every round commits what it handed over.
void Recorder::Run::drain_after_stop() {
  reader_->stop(!limit_reached_);
  while (!limit_reached_) {
    const bool ended = reader_->status().ended;
    commit_round();
    if (ended) break;
    pollfd fd{reader_->fd(), POLLIN, 0};
    ::poll(&fd, 1, 100);
    reader_->clear_wake();
  }
}

// A source that fails (a device gone, a read error): keep what was read and close the session;
// the caller rethrows the failure.
void Recorder::Run::abandon() noexcept {
  if (control_ != nullptr) control_->close();
  try {
    reader_.reset();  // stopped and joined: nothing reads any more
    end_open();
  } catch (...) {  // NOLINT(bugprone-empty-catch): the first failure is the one to report
  }
}

RecordCounters Recorder::Run::finish() {
  reader_.reset();
  if (control_ != nullptr) control_->close();
  end_open();
  counters_.session_id = ended_session_;
  snapshot();
  if (options_.on_commit) options_.on_commit(last_committed_);
  if (options_.on_progress) options_.on_progress(counters_);
  return counters_;
}

// ---- progress ----

void Recorder::Run::snapshot() {
  counters_.channels.clear();
  for (const auto& c : recorder_.channels_) {
    auto copy = c.counters;
    copy.suppressed = c.gate.suppressed();
    counters_.channels.push_back(copy);
  }
  if (writer_) last_committed_ = std::max(last_committed_, writer_->last_committed_seq());
  counters_.last_committed_seq = last_committed_;
}

void Recorder::Run::report_progress() {
  last_progress_ = core::monotonic_now();
  snapshot();
  if (options_.on_progress) options_.on_progress(counters_);
}

}  // namespace m2mlat::capture
