// The durable store: one SQLite file (WAL mode) holding sessions, events, clock samples, recorded
// losses, raw rate samples and markers of one node or of a whole campaign.
//
// Guarantees: a batch is appended in one transaction, all or nothing; once append() returns, the
// batch survives a process crash (and a power loss with Durability::full); a crash during a batch
// leaves the file intact (integrity_check stays ok) without any part of that batch; a reopened
// store continues with larger sequence numbers. Bad input is refused with a message naming the
// store and the field, and changes nothing stored.
//
// One Store object per thread. Several processes may open the same file (a recorder writing, a
// server reading): WAL lets readers proceed during a write, and the busy timeout makes a second
// writer wait instead of failing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::store {

class Store {
 public:
  // Opens (creating if allowed) and migrates the store. Throws core::Error: no_input if it does not
  // exist and may not be created; data if the file is not an m2mlat store or has a newer schema.
  static Store open(const std::string& path, const Options& options = {});

  Store(Store&&) noexcept;
  Store& operator=(Store&&) noexcept;
  ~Store();

  const std::string& path() const;
  int schema_version() const;
  std::string created_by() const;    // "m2mlat <version>" that created the file
  std::string journal_mode() const;  // "wal" for a store opened by m2mlat
  int synchronous() const;           // SQLite's PRAGMA synchronous: 0 off, 1 normal, 2 full
  // A random 128-bit identity (32 hex digits) made when the file was created: a campaign store
  // tells origin stores apart by it.
  std::string store_id() const;

  // Sessions. begin_session ignores session.id and fills an empty software_version with this
  // build's; it returns the new id. end_session refuses an unknown or already ended session; with
  // `config_json` (valid JSON) it also replaces the session's configuration in the same transaction:
  // what a recorder learnt while running (`m2mlat led`: the largest write bound). ingest() carries
  // that configuration with the end.
  std::int64_t begin_session(const Session& session);
  void end_session(std::int64_t id, core::TimePoint end, const std::optional<std::string>& config_json = {});
  // Sessions of `node` still open when a recorder starts were cut (kill -9, power loss): each is
  // ended at the latest time it holds (its last committed event or clock sample on its start's
  // clock; its start if none) and gets a loss of kind "restart" (channel empty, detected_at = now,
  // first_missing = the session's last committed seq + 1, count 1: how many edges the crash took
  // is unknown, at most the batch not yet committed), one transaction. Returns the cut sessions,
  // as now stored. One recorder per node and store: a live recorder's session would be cut too.
  std::vector<Session> close_cut_sessions(const std::string& node, core::TimePoint now);
  std::vector<Session> sessions() const;  // in id order
  std::optional<Session> session(std::int64_t id) const;

  // Appends everything in one transaction. The events' session must exist, be open and have the
  // events' node; losses and clock samples name their own (open) session.
  AppendResult append(const Batch& batch);
  // Shorthands for append(); append_events returns the first event's seq (0 for no events).
  std::int64_t append_events(std::int64_t session_id, std::span<const core::Event> events);
  void append_clock_samples(std::span<const ClockSample> samples);
  void append_losses(std::span<const Loss> losses);
  void append_rate_blocks(std::span<const RateBlock> blocks);
  void append_markers(std::span<const MarkerRecord> markers);

  // Up to `limit` events with seq > after_seq, in seq order (the resume-by-seq read).
  std::vector<StoredEvent> events_after(std::int64_t after_seq, std::size_t limit) const;
  // Events with from <= time <= to (both ends included, so INT64 extremes are reachable), on
  // from's clock, matching the filter, in time order (ties in seq order). from and to must be on
  // the same clock.
  std::vector<StoredEvent> events_in_time(core::TimePoint from, core::TimePoint to,
                                          const EventFilter& filter = {}) const;
  // The same selection as events_in_time, as two columns: for pairing large sets.
  Timestamps timestamps(core::TimePoint from, core::TimePoint to, const EventFilter& filter = {}) const;

  // Clock samples of one session (or all), optionally only those with from <= time <= to, in
  // time order.
  std::vector<ClockSample> clock_samples(std::optional<std::int64_t> session_id = {}) const;
  std::vector<ClockSample> clock_samples(std::optional<std::int64_t> session_id, core::TimePoint from,
                                         core::TimePoint to) const;
  // Losses of one session (or all), in the order recorded.
  std::vector<Loss> losses(std::optional<std::int64_t> session_id = {}) const;
  // Up to `limit` clock samples / losses with id > after_id, in id order (resume-by-id reads).
  std::vector<StoredClockSample> clock_samples_after(std::int64_t after_id, std::size_t limit) const;
  std::vector<StoredLoss> losses_after(std::int64_t after_id, std::size_t limit) const;

  // Raw rate samples (a gyroscope's). The traces stored, by session id then channel:
  std::vector<RateChannel> rate_channels() const;
  // One channel's trace of a session, its blocks joined in time order. Throws core::Error: no_input
  // if there is none; data if its blocks disagree on the clock or the scale, or a BLOB is damaged
  // (naming the table and row).
  core::RateTrace rate_trace(std::int64_t session_id, const std::string& channel) const;
  // Only the trace's last `tail_ns`: the blocks that end within tail_ns of its newest stamp (so a
  // little more, at most one block). What a live view reads each refresh, whatever the trace's length.
  core::RateTrace rate_trace_tail(std::int64_t session_id, const std::string& channel,
                                  std::int64_t tail_ns) const;
  // Up to `limit` blocks with id > after_id, in id order (the resume-by-id read of merge).
  std::vector<StoredRateBlock> rate_blocks_after(std::int64_t after_id, std::size_t limit) const;

  // Markers (software markers, markers read from recordings): up to `limit` with id > after_id in id
  // order (the resume-by-id read), or those of one session (or all) in time order (ties in id order).
  std::vector<StoredMarker> markers_after(std::int64_t after_id, std::size_t limit) const;
  std::vector<StoredMarker> markers(std::optional<std::int64_t> session_id = {}) const;

  // Campaign stores. ingest() appends, all or nothing, what `batch` holds beyond this store's cursor
  // for batch.origin: origin sessions are mapped to local ones (made on first sight, their end set
  // when it becomes known), events/samples/losses/rate blocks/markers get local seqs/ids, and the cursor advances in the
  // same transaction, so every origin item is stored exactly once however often it is given.
  // Returns the new cursor. Refuses (changing nothing) items naming a session the batch does not
  // carry and never carried before, and an origin equal to this store's own id.
  IngestCursor ingest(const IngestBatch& batch);
  IngestCursor ingest_cursor(const std::string& origin) const;
  // The origins this store has taken from, sorted.
  std::vector<std::string> origins() const;

  // The distinct channel names of a session's events, sorted.
  std::vector<std::string> channels(std::int64_t session_id) const;

  std::int64_t last_seq() const;  // the largest committed seq; 0 for no events
  std::int64_t event_count(std::optional<std::int64_t> session_id = {}) const;
  // Throws core::Error(data) naming the table, row and field of the first row breaking the schema's rules
  // (CHECKs, references, the spans' counts): a file edited by another tool. One scan of every table (merge).
  // events_in_time and timestamps check what they read (they would leave such rows out without a word):
  // other tables once per Store, events by seq range, once a range (docs/store.md "Checking rows by range").
  void check_rows() const;

  // PRAGMA integrity_check is "ok" and no foreign key is dangling.
  bool integrity_ok() const;

 private:
  friend class WholeWrite;
  struct Impl;
  explicit Store(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Makes everything a Store writes from construction to commit() one transaction (each write's own
// transaction inside it becomes a savepoint): a command that fails, or is interrupted (SIGINT,
// SIGKILL, a power cut), before commit() leaves the store as it was. Readers see none of it until
// then. Neither copied nor moved; at most one per Store at a time.
class WholeWrite {
 public:
  explicit WholeWrite(Store& store);
  WholeWrite(const WholeWrite&) = delete;
  WholeWrite& operator=(const WholeWrite&) = delete;
  ~WholeWrite();
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// True if `path` is a non-empty regular file that SQLite reads as a database (how the commands tell
// a store from a data file). Checked by stat() and a read-only SQLite connection, never a raw
// open(), so it is safe in a process that holds connections to that very file.
bool is_sqlite_database(const std::string& path);

// Removes a store a failed command made (the file, its -wal, -shm and -journal; unlink() opens
// nothing). Only for a store no connection of this process is open on.
void remove_store_files(const std::string& path);

}  // namespace m2mlat::store
