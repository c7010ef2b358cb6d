// The store's private state, shared by the files that implement Store (store.cpp, ingest.cpp): the
// connection, its options and the statements prepared once per connection. Not part of the API.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/event_ranges.hpp"
#include "m2mlat/store/event_spans.hpp"
#include "m2mlat/store/rows.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::store {

// Resets a reused statement when the scope ends, also by an exception, so that it does not keep a
// read transaction open (which would stop checkpoints from shrinking the WAL).
class ResetOnExit {
 public:
  explicit ResetOnExit(sqlite::Statement& statement) : statement_(statement) {}
  ResetOnExit(const ResetOnExit&) = delete;
  ResetOnExit& operator=(const ResetOnExit&) = delete;
  ~ResetOnExit() { statement_.reset(); }

 private:
  sqlite::Statement& statement_;
};

// One read transaction (BEGIN DEFERRED, ended by the destructor: it wrote nothing), so that the
// checks before a read and the read see the store as of one moment. Inside a transaction already
// it does nothing.
class ReadTransaction {
 public:
  explicit ReadTransaction(sqlite::Database& db) : db_(db.in_transaction() ? nullptr : &db) {
    if (db_) db_->exec("BEGIN");
  }
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;
  ~ReadTransaction() {
    if (!db_ || !db_->in_transaction()) return;
    try {
      db_->exec("ROLLBACK");
    } catch (const core::Error&) {  // nothing was written; SQLite ends it when the connection closes
    }
  }

 private:
  sqlite::Database* db_;
};

struct Store::Impl {
  Impl(sqlite::Database database, Options opts, int schema_version)
      : db(std::move(database)),
        options(opts),
        version(schema_version),
        insert_event(db, rows::kInsertEvent),
        insert_events(db, rows::insert_events_sql(rows::kEventsPerInsert)),
        insert_loss(db, rows::kInsertLoss),
        insert_clock_sample(db, rows::kInsertClockSample),
        insert_rate_block(db, rows::kInsertRateBlock),
        insert_marker(db, rows::kInsertMarker),
        insert_span(db, event_spans::kInsertSpan),
        session_state(db, "SELECT node, end_ns IS NOT NULL FROM sessions WHERE id = ?1"),
        // LEFT JOIN: an event naming a missing session is refused by read_event, not skipped.
        events_after(db, fmt::format("SELECT {} FROM events e LEFT JOIN sessions s ON s.id = e.session_id "
                                     "WHERE e.seq > ?1 ORDER BY e.seq LIMIT ?2",
                                     rows::kEventColumns)) {}

  // What a write needs to know about a session, read under the write lock.
  struct SessionState {
    std::string node;
    bool ended = false;
  };
  std::optional<SessionState> lookup(std::int64_t id) {
    ResetOnExit done(session_state);
    session_state.bind(1, id);
    if (!session_state.step()) return std::nullopt;
    return SessionState{std::string(session_state.column_text(0)), session_state.column_int64(1) != 0};
  }
  // The session must exist and be open; returns its node.
  std::string require_open_session(std::int64_t id, std::string_view what) {
    const auto state = lookup(id);
    if (!state)
      core::throw_data_error({db.path(), 0}, fmt::format("{}: session {} does not exist", what, id));
    if (state->ended)
      core::throw_data_error({db.path(), 0}, fmt::format("{}: session {} has ended", what, id));
    return state->node;
  }

  void require_writable() const {
    if (options.read_only)
      throw core::Error(core::ErrorKind::usage, fmt::format("{}: the store is open read-only", db.path()));
  }

  event_ranges::Checked& ranges();  // refreshed with the spans written since the last call
  // Before a read: the other tables' rules once per Store, then the events of the seq ranges the
  // read's spans lie in that were not checked yet (docs/store.md "Checking rows by range"). Throws
  // core::Error(data) naming the store, table, row and field.
  void check_read(core::TimePoint from, core::TimePoint to, const EventFilter& filter);

  sqlite::Database db;
  Options options;
  int version;
  bool tables_checked = false;                   // row_check::check_tables ran on this connection
  std::optional<event_ranges::Checked> checked;  // made by the first read that checks rows
  sqlite::Statement insert_event;
  sqlite::Statement insert_events;  // rows::kEventsPerInsert rows
  sqlite::Statement insert_loss;
  sqlite::Statement insert_clock_sample;
  sqlite::Statement insert_rate_block;
  sqlite::Statement insert_marker;
  sqlite::Statement insert_span;
  sqlite::Statement session_state;
  sqlite::Statement events_after;
};

}  // namespace m2mlat::store
