// The recorder's reading thread: it drains a Source into a bounded queue of chunks, so that reading
// the kernel's buffer never waits on a commit (SQLite's work and the fsync) in the writing thread.
//
// The bound is a pool of `chunks` ReadResults of up to `chunk_events` events each. When every chunk
// is filled and none has been taken, the thread stops reading: the kernel's buffer fills, the kernel
// drops the oldest events, and the source reports them as a sequence-number gap. So a full queue
// loses nothing silently, and nothing is dropped in user space. Chunks are handed over in the order
// they were read; the consumer takes all of them at once, the one being filled included, and gives
// them back for reuse once it has stored them (so that, once warm, reading allocates nothing).
//
// When events come faster than one per `coalesce` (two reads that found events less than that
// apart), the thread waits `coalesce` after each read before it looks again, so that one wake-up
// reads many events (one read(2) of up to 1024) instead of one. A read is then late by at most
// coalesce plus scheduling delay, less than the time the kernel's buffer of 1024 events lasts at
// any rate a sensor produces (10 ms at 100,000 edges/s; a Hall sensor on a steering wheel gives
// well under 1,000). Slower events are read as they come.
#pragma once

#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "m2mlat/capture/source.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

struct SourceReaderOptions {
  std::size_t chunk_events = 1024;                         // events per chunk, at most this many per read
  std::size_t chunks = 16;                                 // the queue's bound, in chunks
  // Pause after a read that found events (0: none). 5 ms rather than 1: at 10,000 edges/s in the
  // guest it took record's CPU per event from 1.3-1.8x gpiomon's to 0.5-0.8x (docs/testing.md); the
  // commit interval (100 ms) still dominates the latency.
  core::Duration coalesce = std::chrono::milliseconds(5);
  std::size_t wake_events = 512;  // the consumer's descriptor turns readable once this many are queued
  // How long a stop with drain keeps reading. A kernel's buffer (at most 1024 events a line) is read
  // in well under a millisecond; a source that always has more (an unpaced simulation, a line that
  // never stops firing) would otherwise keep the reader, and the process, going forever.
  core::Duration drain_limit = std::chrono::milliseconds(250);
};

class SourceReader {
 public:
  // Starts the thread; the source is read only by it from now on, until the destructor returns.
  SourceReader(Source& source, SourceReaderOptions options);
  // Stops the thread without draining (stop(false)) and joins it.
  ~SourceReader();
  SourceReader(const SourceReader&) = delete;
  SourceReader& operator=(const SourceReader&) = delete;

  // An eventfd that polls readable when the consumer should look: the first events after a take
  // (to start its commit clock), wake_events queued, or the thread ended. clear_wake() consumes it.
  int fd() const { return wake_consumer_fd_.get(); }
  void clear_wake();

  struct Status {
    std::size_t events = 0;               // queued and not taken
    std::optional<core::Duration> first;  // CLOCK_MONOTONIC when the oldest of them was read
    bool ended = false;  // the thread has ended: stopped, source finished, or failed (error())
  };
  Status status() const;

  // Appends every queued chunk to `out`, in read order. Each holds events, gaps and clock samples as
  // Source::read gives them; `finished` is set on the last one of a finished source.
  void take(std::vector<std::unique_ptr<ReadResult>>& out);
  // Returns taken chunks for reuse (empties `chunks`).
  void give_back(std::vector<std::unique_ptr<ReadResult>>& chunks);

  // Asks the thread to end; with `drain` it first reads until the source has nothing more (what the
  // kernel still buffers at a stop) or drain_limit has passed, waiting for chunks to be given back as
  // needed. Returns at once; status().ended says when the thread is done.
  void stop(bool drain);
  // The failure that ended the thread (a source that could not be read), or null.
  std::exception_ptr error() const;

 private:
  void run();
  // Reads once into the chunk being filled; the number of items read (events, gaps, clock samples),
  // 0 if none or if a stop without drain interrupted the wait for a free chunk.
  std::size_t read_once();
  // Waits until the source may have something, a stop is asked for, or `timeout` passes (negative:
  // no timeout).
  void wait_source(core::Duration timeout);
  void wake_consumer();

  Source& source_;
  SourceReaderOptions options_;
  core::Fd wake_consumer_fd_;  // eventfd: the reader -> the consumer
  core::Fd wake_reader_fd_;    // eventfd: stop() -> the reader

  mutable std::mutex mutex_;
  std::condition_variable chunk_freed_;
  std::vector<std::unique_ptr<ReadResult>> free_;
  std::vector<std::unique_ptr<ReadResult>> ready_;
  std::unique_ptr<ReadResult> current_;  // being filled
  std::size_t queued_events_ = 0;
  std::optional<core::Duration> first_;
  bool stop_ = false, drain_ = false, ended_ = false;
  core::Duration drain_until_{0};  // CLOCK_MONOTONIC: a drain ends here at the latest
  std::exception_ptr error_;
  std::optional<core::Duration> last_read_;  // CLOCK_MONOTONIC of the last read that found events
  std::thread thread_;
};

// The writing thread gives a real-time policy up to the reading thread while it lives: a commit on a
// SCHED_FIFO thread would keep a reader of the same priority off a single CPU for as long as it
// takes. The thread's policy and priority are restored on destruction. Does nothing for a thread
// that is not real-time.
class LeaveRealtimeToReader {
 public:
  LeaveRealtimeToReader();
  ~LeaveRealtimeToReader();
  LeaveRealtimeToReader(const LeaveRealtimeToReader&) = delete;
  LeaveRealtimeToReader& operator=(const LeaveRealtimeToReader&) = delete;

 private:
  bool changed_ = false;
  int policy_ = 0;
  sched_param param_{};
};

}  // namespace m2mlat::capture
