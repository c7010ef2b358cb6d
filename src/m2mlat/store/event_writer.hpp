// The batching writer: buffers events (and the losses and clock samples that go with them) and
// commits them to the store in one transaction per batch.
//
// A batch is committed when it holds max_batch records, when its oldest record is max_age old
// (checked on every add, unless WriterOptions::age_on_add is off, and by poll(), which an idle
// capture loop calls), on flush() and in the destructor. last_committed_seq() is the acknowledged point:
// every event with a seq up to it is committed, and only such events may be served or acknowledged to anyone.
// A crash loses at most the records still buffered.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::store {

struct WriterOptions {
  std::size_t max_batch = 512;                              // records per commit, at least 1
  core::Duration max_age = std::chrono::milliseconds(100);  // longest a record waits for its commit
  // Monotonic time source, ns since any epoch; empty = CLOCK_MONOTONIC. Tests inject their own.
  std::function<core::Duration()> now;
  // false: the age is checked by poll() only, and the clock is read once per batch instead of once
  // per record (for a caller that keeps the time itself, as the recorder does; where the
  // clocksource has no vDSO path, in some VMs, each clock read is a system call).
  bool age_on_add = true;
  // Called after every successful commit with the batch just committed and the store's answer
  // (the recorder measures edge -> durable commit latency there). Must not throw.
  std::function<void(const Batch& committed, const AppendResult& result)> on_commit;
};

class EventWriter {
 public:
  // The session must exist and be open. The store must outlive the writer.
  EventWriter(Store& store, std::int64_t session_id, WriterOptions options = {});
  EventWriter(const EventWriter&) = delete;
  EventWriter& operator=(const EventWriter&) = delete;
  // Commits what is buffered. A failure here cannot be reported: call flush() first to see it.
  ~EventWriter();

  // Buffers one record and commits if the batch is full or old enough. A record the store would
  // refuse (wrong node or session, empty channel, invalid JSON, ...) throws core::Error(data) and
  // is not buffered. A failed commit throws and keeps the batch, so that flush() can retry.
  void add(const core::Event& event);
  void add(const Loss& loss);
  void add(const ClockSample& sample);
  void add(const RateBlock& block);  // a block of raw rate samples of the writer's session

  // Commits if the oldest buffered record is at least max_age old; true if it committed.
  bool poll();
  // Commits everything buffered (nothing to do if empty).
  AppendResult flush();

  // Every event of the store with seq <= this is committed (0: none yet).
  std::int64_t last_committed_seq() const { return last_committed_seq_; }
  std::size_t pending() const;                                          // records buffered, not yet committed
  std::uint64_t committed_events() const { return committed_events_; }  // by this writer
  std::int64_t session_id() const { return batch_.session_id; }

 private:
  void buffered();  // after a record was added: start the age clock, commit if due
  bool due() const;
  core::Duration now() const;

  Store& store_;
  WriterOptions options_;
  std::string node_;  // the session's node, which every event must carry
  Batch batch_;
  core::Duration oldest_{0};  // when the first record of the current batch was added
  std::int64_t last_committed_seq_ = 0;
  std::uint64_t committed_events_ = 0;
};

}  // namespace m2mlat::store
