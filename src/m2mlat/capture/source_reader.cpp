// The reading thread, its bounded pool of chunks, and the two eventfds between it and the consumer.
#include "m2mlat/capture/source_reader.hpp"

#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "m2mlat/capture/recorder.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

namespace {

core::Fd make_eventfd() {
  core::Fd fd(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK));
  if (!fd) throw core::Error(core::ErrorKind::io, fmt::format("eventfd: {}", std::strerror(errno)));
  return fd;
}

void signal_fd(int fd) {
  const std::uint64_t one = 1;
  // EAGAIN only when the counter is about to overflow, which is readable anyway.
  [[maybe_unused]] const auto n = ::write(fd, &one, sizeof one);
}

void drain_fd(int fd) {
  std::uint64_t value = 0;
  [[maybe_unused]] const auto n = ::read(fd, &value, sizeof value);
}

timespec to_timespec(core::Duration d) {
  const auto ns = std::max<std::int64_t>(0, d.count());
  return {static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
}

std::size_t items(const ReadResult& r) { return r.events.size() + r.gaps.size() + r.clock_samples.size(); }

}  // namespace

SourceReader::SourceReader(Source& source, SourceReaderOptions options) : source_(source), options_(options) {
  options_.chunk_events = std::max<std::size_t>(options_.chunk_events, 1);
  options_.chunks = std::max<std::size_t>(options_.chunks, 2);
  // The consumer must be woken before the pool is full, or the reader would wait for it.
  options_.wake_events =
      std::clamp<std::size_t>(options_.wake_events, 1, (options_.chunks - 1) * options_.chunk_events);
  wake_consumer_fd_ = make_eventfd();
  wake_reader_fd_ = make_eventfd();
  for (std::size_t i = 0; i < options_.chunks; ++i) {
    auto chunk = std::make_unique<ReadResult>();
    chunk->events.reserve(options_.chunk_events);
    free_.push_back(std::move(chunk));
  }
  thread_ = std::thread([this] { run(); });
}

SourceReader::~SourceReader() {
  stop(false);
  if (thread_.joinable()) thread_.join();
}

void SourceReader::clear_wake() { drain_fd(wake_consumer_fd_.get()); }

SourceReader::Status SourceReader::status() const {
  std::lock_guard lock(mutex_);
  return {queued_events_, first_, ended_};
}

void SourceReader::take(std::vector<std::unique_ptr<ReadResult>>& out) {
  std::lock_guard lock(mutex_);
  for (auto& chunk : ready_) out.push_back(std::move(chunk));
  ready_.clear();
  if (current_ && items(*current_) > 0) out.push_back(std::move(current_));
  queued_events_ = 0;
  first_.reset();
}

void SourceReader::give_back(std::vector<std::unique_ptr<ReadResult>>& chunks) {
  {
    std::lock_guard lock(mutex_);
    for (auto& chunk : chunks) {
      chunk->clear();
      free_.push_back(std::move(chunk));
    }
  }
  chunks.clear();
  chunk_freed_.notify_one();
}

void SourceReader::stop(bool drain) {
  {
    std::lock_guard lock(mutex_);
    if (stop_) drain = drain && drain_;  // a second request can cancel a drain, never ask for one
    if (drain && !drain_) drain_until_ = core::monotonic_now() + options_.drain_limit;
    stop_ = true;
    drain_ = drain;
  }
  chunk_freed_.notify_one();
  signal_fd(wake_reader_fd_.get());
}

std::exception_ptr SourceReader::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void SourceReader::wake_consumer() { signal_fd(wake_consumer_fd_.get()); }

void SourceReader::wait_source(core::Duration timeout) {
  pollfd fds[2] = {{wake_reader_fd_.get(), POLLIN, 0}, {source_.fd(), POLLIN, 0}};
  const auto ts = to_timespec(timeout);
  if (::ppoll(fds, 2, timeout.count() < 0 ? nullptr : &ts, nullptr) < 0 && errno != EINTR)
    throw core::Error(core::ErrorKind::io, fmt::format("poll: {}", std::strerror(errno)));
}

std::size_t SourceReader::read_once() {
  std::unique_lock lock(mutex_);
  while (!current_ || current_->events.size() >= options_.chunk_events) {
    if (current_) ready_.push_back(std::move(current_));
    // The bound: with every chunk in use, wait for the consumer rather than read (the kernel keeps
    // buffering, and drops the oldest with a seqno gap if this lasts).
    chunk_freed_.wait(lock, [&] { return !free_.empty() || (stop_ && !drain_); });
    if (free_.empty()) return 0;
    current_ = std::move(free_.back());
    free_.pop_back();
  }
  const auto before = items(*current_);
  const auto events_before = current_->events.size();
  // Under the lock: the consumer may take this chunk only between reads; a read does not block.
  source_.read(*current_, options_.chunk_events - events_before);
  const auto got = items(*current_) - before;
  if (got == 0 && !current_->finished) return 0;
  const bool was_empty = queued_events_ == 0 && !first_;
  if (!first_) first_ = core::monotonic_now();
  const auto queued_before = queued_events_;
  queued_events_ += current_->events.size() - events_before;
  const bool finished = current_->finished;
  if (finished) {
    ready_.push_back(std::move(current_));
    ended_ = true;
  }
  lock.unlock();
  if (was_empty || finished ||
      (queued_before < options_.wake_events && queued_events_ >= options_.wake_events))
    wake_consumer();
  return got;
}

void SourceReader::run() {
  // Signals are for the consumer's thread (its signalfd); this thread only reads.
  sigset_t all;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, nullptr);
  const bool pollable = source_.fd() >= 0;
  try {
    for (;;) {
      bool drain = false;
      core::Duration drain_until{0};
      {
        std::lock_guard lock(mutex_);
        if (ended_) break;  // the source finished
        if (stop_ && !drain_) break;
        drain = stop_;
        drain_until = drain_until_;
      }
      if (drain) {
        // Read until the source has nothing more (the kernel's buffer at a stop), within the limit.
        if (core::monotonic_now() >= drain_until || read_once() == 0) break;
        continue;
      }
      const auto got = read_once();
      if (got > 0 && pollable && options_.coalesce.count() > 0) {
        // Events come faster than one per coalesce period: let them accumulate, so that the next
        // read takes many. Slower ones are read as they come: a pause would only add a wake-up.
        const auto now = core::monotonic_now();
        if (last_read_ && now - *last_read_ < options_.coalesce) {
          pollfd fd{wake_reader_fd_.get(), POLLIN, 0};  // a stop ends the pause at once
          const auto ts = to_timespec(options_.coalesce);
          ::ppoll(&fd, 1, &ts, nullptr);
        }
        last_read_ = now;
      }
      if (got == 0) wait_source(pollable ? core::Duration{-1} : source_.poll_interval());
    }
  } catch (...) {
    std::lock_guard lock(mutex_);
    error_ = std::current_exception();
  }
  {
    std::lock_guard lock(mutex_);
    if (current_ && items(*current_) > 0) ready_.push_back(std::move(current_));
    ended_ = true;
  }
  wake_consumer();
}

LeaveRealtimeToReader::LeaveRealtimeToReader() {
  if (pthread_getschedparam(pthread_self(), &policy_, &param_) != 0) return;
  if (policy_ != SCHED_FIFO && policy_ != SCHED_RR) return;
  const sched_param normal{};
  changed_ = pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal) == 0;
}

LeaveRealtimeToReader::~LeaveRealtimeToReader() {
  if (changed_) pthread_setschedparam(pthread_self(), policy_, &param_);
}

}  // namespace m2mlat::capture
