// The recorder of one node: source -> refractory gate per channel -> store::EventWriter, with every
// gap the source reports stored as a store::Loss. Two threads: a SourceReader drains the source
// (the kernel's buffer) into a bounded queue, so that reading never waits on a commit; the calling
// thread waits on that queue and on a stop descriptor (StopSignal's signalfd in the CLI, anything
// readable in tests), takes what is queued when a batch is full or its oldest event has waited the
// commit interval, and commits it. An event counts as stored only once its commit has returned. On
// stop the reader drains what the kernel still buffers, and all of it is committed before the
// session ends. With a SessionControl (the agent) sessions are begun and ended while it runs;
// between a stop and the next begin the edges it reads are counted as dropped and not stored.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/capture/latency_histogram.hpp"
#include "m2mlat/capture/raw_round.hpp"
#include "m2mlat/capture/refractory_gate.hpp"
#include "m2mlat/capture/session_control.hpp"
#include "m2mlat/capture/source.hpp"
#include "m2mlat/capture/source_reader.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::capture {

struct ChannelCounters {
  std::string channel;
  std::uint64_t events = 0;             // stored
  std::uint64_t suppressed = 0;         // refused by the refractory gate (bounces)
  std::uint64_t lost = 0;               // missing according to the kernel's sequence numbers
  std::optional<core::TimePoint> last;  // the last stored event's timestamp
};

struct RecordCounters {
  std::int64_t session_id = 0;            // the open session (the last one once run() returned); 0: none
  std::vector<ChannelCounters> channels;  // in the source's channel order
  std::uint64_t node_lost = 0;            // losses not tied to a channel (kmsg records)
  std::uint64_t events = 0;               // stored, all channels
  std::uint64_t dropped = 0;              // read while no session was open: not stored
  std::int64_t last_committed_seq = 0;    // the store's acknowledged point
  std::string stop_reason;                // "SIGINT", "count", "duration", "source finished", "stop"
  // Sessions of this node found open at the start (cut by a crash) and closed with a "restart"
  // loss (Store::close_cut_sessions), in id order.
  std::vector<std::int64_t> cut_sessions;
  // From each stored event's timestamp to the return of the commit that made it durable (events on
  // CLOCK_REALTIME only: the commit's end is read on that clock), ns.
  LatencyHistogram commit_latency;
  // Events left out of commit_latency because they were stamped before this run began (a kernel
  // log replayed from a file): their "latency" would be their age, not the recorder's delay.
  std::uint64_t commit_latency_replayed = 0;
  // The newest clock sample stored, from the source itself (the simulated rig's daemons) or from
  // before_commit (the clock monitor); what the agent's /v1/status reports as its clock.
  std::optional<store::ClockSample> last_clock;
};

struct RecorderOptions {
  store::Session session;  // node, role, label, scenario, config_json; start and end are the recorder's
  std::map<std::string, core::Duration> refractory;                 // per channel; missing = none
  std::size_t batch = 512;                                          // events per commit
  core::Duration commit_interval = std::chrono::milliseconds(100);  // longest an event waits for its commit
  // The reading thread's settings (events per read, queue bound, pause when events come fast); its
  // wake_events is set from `batch`.
  SourceReaderOptions reader;
  std::uint64_t max_events = 0;    // stop after this many stored events (0: no limit)
  core::Duration max_duration{0};  // stop after this long (0: no limit)
  // Called at most every progress_interval and once at the end (live counters).
  std::function<void(const RecordCounters&)> on_progress;
  core::Duration progress_interval = std::chrono::milliseconds(250);

  // Session control from other threads (nullptr: one session, from start to stop). The recorder
  // carries requests out between batches and closes the control when it stops.
  SessionControl* control = nullptr;
  bool start_session = true;  // false: begin with no session open (only with a control)
  // Called once before every round of commits (what is queued is taken and committed) with the open
  // session's id: may append clock samples for that session, which are committed with the events.
  // Not called without a session.
  std::function<void(std::int64_t session_id, std::vector<store::ClockSample>&)> before_commit;
  // Called beside before_commit (every round, once more when a session ends, with its end time,
  // and once after the stop with `final` set; raw_round.hpp): may add blocks of raw rate samples and
  // losses for the round's session (the gyroscope channel, gyro_channel.hpp), committed with the
  // round's events. Also called every commit interval while no session is open (session_id 0),
  // when whatever it adds is not stored.
  std::function<void(const RawRound&, std::vector<store::RateBlock>&, std::vector<store::Loss>&)> raw_samples;
  // Called after a round that committed, with the store's new acknowledged seq (to wake readers).
  std::function<void(std::int64_t last_committed_seq)> on_commit;
};

class Recorder {
 public:
  Recorder(store::Store& store, Source& source, RecorderOptions options);
  // Runs until stop_fd polls readable (-1: never), a limit is reached or the source finishes. A
  // readable StopSignal's signal is taken by the caller; here only readability matters.
  RecordCounters run(int stop_fd, const std::function<std::string()>& stop_name = {});

 private:
  class Run;  // one call of run(): its state and steps (recorder.cpp)
  struct Channel {
    ChannelCounters counters;
    RefractoryGate gate;
  };
  Channel& channel(const std::string& name);
  Channel& channel_of(const core::Event& event);  // channel(), remembering the last one looked up
  std::int64_t begin(const store::Session& session);

  store::Store& store_;
  Source& source_;
  RecorderOptions options_;
  std::map<std::string, std::size_t> index_;
  std::vector<Channel> channels_;
  std::size_t last_channel_ = 0;
};

}  // namespace m2mlat::capture
