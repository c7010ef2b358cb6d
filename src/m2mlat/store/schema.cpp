// The schema's versions (1 to 5) and the migration runner. Columns, types and units are documented in
// docs/store.md; how rows map to the in-memory values is in rows.cpp.
#include "m2mlat/store/schema.hpp"

#include <fmt/format.h>

#include <array>
#include <map>
#include <set>
#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/version.hpp"

namespace m2mlat::store::schema {

namespace {

// Version 1. Times are (clock, t_ns) pairs: clock is core::Clock's stored value, t_ns int64 ns.
// uint64 counters (seqno, line_seqno, first_missing, count) are stored as the int64 with the same
// bits. events.seq is the rowid: a new row gets max(seq) + 1, and since events are never deleted
// (the store has no way to), a committed seq is never given again; a rolled-back batch's seqs
// were never acknowledged, so reusing them is safe. (AUTOINCREMENT would cost ~20% of the insert
// time for a guarantee only deletion needs.) Session ids use AUTOINCREMENT: sessions are few.
constexpr std::string_view kVersion1 = R"sql(
CREATE TABLE meta (
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
) WITHOUT ROWID;

CREATE TABLE sessions (
  id               INTEGER PRIMARY KEY AUTOINCREMENT,
  label            TEXT NOT NULL,
  scenario         TEXT NOT NULL,
  node             TEXT NOT NULL CHECK (node <> ''),
  role             INTEGER NOT NULL CHECK (role BETWEEN 0 AND 2),
  config_json      TEXT NOT NULL,
  start_clock      INTEGER NOT NULL CHECK (start_clock BETWEEN 0 AND 3),
  start_ns         INTEGER NOT NULL,
  end_clock        INTEGER CHECK (end_clock BETWEEN 0 AND 3),
  end_ns           INTEGER,
  software_version TEXT NOT NULL,
  CHECK ((end_clock IS NULL) = (end_ns IS NULL))
);

CREATE TABLE events (
  seq        INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions (id),
  channel    TEXT NOT NULL CHECK (channel <> ''),
  edge       INTEGER NOT NULL CHECK (edge IN (0, 1)),
  clock      INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  t_ns       INTEGER NOT NULL,
  seqno      INTEGER NOT NULL,
  line_seqno INTEGER NOT NULL,
  flags      INTEGER NOT NULL CHECK (flags BETWEEN 0 AND 4294967295)
);
CREATE INDEX events_by_time ON events (clock, t_ns);
CREATE INDEX events_by_session ON events (session_id, channel, clock, t_ns);

CREATE TABLE clock_samples (
  id           INTEGER PRIMARY KEY,
  session_id   INTEGER NOT NULL REFERENCES sessions (id),
  clock        INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  t_ns         INTEGER NOT NULL,
  source       TEXT NOT NULL CHECK (source <> ''),
  offset_ns    INTEGER NOT NULL,
  max_error_ns INTEGER NOT NULL,
  est_error_ns INTEGER NOT NULL,
  synchronised INTEGER NOT NULL CHECK (synchronised IN (0, 1)),
  detail_json  TEXT NOT NULL
);
CREATE INDEX clock_samples_by_session ON clock_samples (session_id, clock, t_ns);

CREATE TABLE losses (
  id            INTEGER PRIMARY KEY,
  session_id    INTEGER NOT NULL REFERENCES sessions (id),
  channel       TEXT NOT NULL,
  clock         INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  t_ns          INTEGER NOT NULL,
  first_missing INTEGER NOT NULL,
  count         INTEGER NOT NULL CHECK (count <> 0),
  kind          TEXT NOT NULL
    CHECK (kind IN ('seqno_gap', 'line_seqno_gap', 'kmsg_gap', 'overflow', 'restart'))
);
CREATE INDEX losses_by_session ON losses (session_id, clock, t_ns);
)sql";

// Version 2: campaign stores. Every store gets a random identity (meta 'store_id', 32 hex digits);
// a store that takes events from others (the coordinator's, merge's) keeps, per origin store, how far
// it has taken each kind (origin seq / ids, 0 = nothing) and which local session mirrors each origin
// session. The cursor row is updated in the transaction that stores the items, so each origin item is
// stored exactly once.
constexpr std::string_view kVersion2 = R"sql(
INSERT INTO meta (key, value) VALUES ('store_id', lower(hex(randomblob(16))));

CREATE TABLE origins (
  origin          TEXT PRIMARY KEY CHECK (origin <> ''),
  event_seq       INTEGER NOT NULL,
  clock_sample_id INTEGER NOT NULL,
  loss_id         INTEGER NOT NULL
);

CREATE TABLE origin_sessions (
  origin            TEXT NOT NULL REFERENCES origins (origin),
  origin_session_id INTEGER NOT NULL,
  session_id        INTEGER NOT NULL UNIQUE REFERENCES sessions (id),
  PRIMARY KEY (origin, origin_session_id)
);
)sql";

// Version 3: a gyroscope's raw samples, in blocks (docs/store.md "Raw rate samples"). A row holds up
// to rate_block::kMaxSamples samples of one channel of one session packed in a BLOB of the layout
// named by `layout` (rate_block.hpp): one row per sample would cost ~40 bytes of row overhead on an
// 18-byte sample, at 29 million samples a drive-hour. first_index is the number of the block's
// first sample in read order (0 = the session's first on the channel), so a missing block or samples
// left out by a keep window show as a jump. first_ns/last_ns (the block's first and last stamp, ns on
// `clock`) select blocks by time without decoding them. The losses table is rebuilt (SQLite cannot
// alter a CHECK) to accept the gyroscope's losses: 'missed_period' (a read deadline passed with no
// read) and 'i2c_error' (a failed bus transfer); ids are kept, so cursors on them stay valid.
// origins gets the cursor of the blocks taken from each origin.
constexpr std::string_view kVersion3 = R"sql(
CREATE TABLE rate_blocks (
  id               INTEGER PRIMARY KEY,
  session_id       INTEGER NOT NULL REFERENCES sessions (id),
  channel          TEXT NOT NULL CHECK (channel <> ''),
  clock            INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  counts_per_deg_s REAL NOT NULL CHECK (counts_per_deg_s > 0),
  first_index      INTEGER NOT NULL CHECK (first_index >= 0),
  count            INTEGER NOT NULL CHECK (count BETWEEN 1 AND 4096),
  first_ns         INTEGER NOT NULL,
  last_ns          INTEGER NOT NULL CHECK (last_ns >= first_ns),
  layout           INTEGER NOT NULL CHECK (layout = 1),
  samples          BLOB NOT NULL CHECK (length(samples) = 18 * count)
);
CREATE INDEX rate_blocks_by_session ON rate_blocks (session_id, channel, first_ns);

CREATE TABLE losses_v3 (
  id            INTEGER PRIMARY KEY,
  session_id    INTEGER NOT NULL REFERENCES sessions (id),
  channel       TEXT NOT NULL,
  clock         INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  t_ns          INTEGER NOT NULL,
  first_missing INTEGER NOT NULL,
  count         INTEGER NOT NULL CHECK (count <> 0),
  kind          TEXT NOT NULL
    CHECK (kind IN ('seqno_gap', 'line_seqno_gap', 'kmsg_gap', 'overflow', 'restart', 'missed_period',
                    'i2c_error'))
);
INSERT INTO losses_v3 (id, session_id, channel, clock, t_ns, first_missing, count, kind)
  SELECT id, session_id, channel, clock, t_ns, first_missing, count, kind FROM losses;
DROP TABLE losses;
ALTER TABLE losses_v3 RENAME TO losses;
CREATE INDEX losses_by_session ON losses (session_id, clock, t_ns);

ALTER TABLE origins ADD COLUMN rate_block_id INTEGER NOT NULL DEFAULT 0;
)sql";

// Version 4: markers (docs/markers.md), software markers received by an agent and markers read from
// recordings, each of a session. source is who took the stamp (markers::StampSource's name);
// uncertainty_ns and sender_ns are NULL when unknown / not given; key may be empty (a marker that
// names no command). origins gets the cursor of the markers taken from each origin.
constexpr std::string_view kVersion4 = R"sql(
CREATE TABLE markers (
  id             INTEGER PRIMARY KEY,
  session_id     INTEGER NOT NULL REFERENCES sessions (id),
  name           TEXT NOT NULL CHECK (name <> ''),
  clock          INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  t_ns           INTEGER NOT NULL,
  source         TEXT NOT NULL CHECK (source <> ''),
  uncertainty_ns INTEGER CHECK (uncertainty_ns >= 0),
  key            TEXT NOT NULL,
  sender_ns      INTEGER,
  origin         TEXT NOT NULL
);
CREATE INDEX markers_by_session ON markers (session_id, clock, t_ns);

ALTER TABLE origins ADD COLUMN marker_id INTEGER NOT NULL DEFAULT 0;
)sql";

// Version 5: event spans (event_spans.hpp) instead of the events table's two per-row indexes, which
// cost most of SQLite's work per stored event. A span is one (session, channel, clock) group of the
// events of one transaction: their seq range, earliest and latest t_ns (ns on `clock`) and number.
// The events already stored get spans of up to 4096 seqs (seq >> 12), so that a time read of an old
// store narrows as well as of a new one; then the two indexes go.
constexpr std::string_view kVersion5 = R"sql(
CREATE TABLE event_spans (
  id         INTEGER PRIMARY KEY,
  session_id INTEGER NOT NULL REFERENCES sessions (id),
  channel    TEXT NOT NULL CHECK (channel <> ''),
  clock      INTEGER NOT NULL CHECK (clock BETWEEN 0 AND 3),
  first_seq  INTEGER NOT NULL CHECK (first_seq >= 1),
  last_seq   INTEGER NOT NULL CHECK (last_seq >= first_seq),
  first_ns   INTEGER NOT NULL,
  last_ns    INTEGER NOT NULL CHECK (last_ns >= first_ns),
  count      INTEGER NOT NULL CHECK (count BETWEEN 1 AND last_seq - first_seq + 1)
);
INSERT INTO event_spans (session_id, channel, clock, first_seq, last_seq, first_ns, last_ns, count)
  SELECT session_id, channel, clock, min(seq), max(seq), min(t_ns), max(t_ns), count(*) FROM events
  GROUP BY seq >> 12, session_id, channel, clock ORDER BY min(seq);
CREATE INDEX event_spans_by_time ON event_spans (clock, last_ns);
CREATE INDEX event_spans_by_session ON event_spans (session_id, channel, clock, first_ns);
DROP INDEX events_by_time;
DROP INDEX events_by_session;
)sql";

constexpr std::array kMigrations{
    Migration{"sessions, events, clock samples, losses, meta", kVersion1},
    Migration{"store identity, origins of a campaign store", kVersion2},
    Migration{"raw rate samples in blocks, the gyroscope's loss kinds", kVersion3},
    Migration{"markers", kVersion4},
    Migration{"event spans instead of the events' per-row indexes", kVersion5},
};

// The tables and columns of a store of the latest version, as the steps above leave them (SQLite's
// own tables left out). Opening a store compares its tables with these instead of running the steps
// on an in-memory database, which cost 13 M instructions (callgrind), a fifth of an idle `record`;
// the unit tests compare this list with the steps' result, so the two cannot drift apart. A new
// step that adds or changes a table updates it.
constexpr std::string_view kLatestTables[][12] = {
    {"meta", "key", "value"},
    {"sessions", "id", "label", "scenario", "node", "role", "config_json", "start_clock", "start_ns",
     "end_clock", "end_ns", "software_version"},
    {"events", "seq", "session_id", "channel", "edge", "clock", "t_ns", "seqno", "line_seqno", "flags"},
    {"clock_samples", "id", "session_id", "clock", "t_ns", "source", "offset_ns", "max_error_ns",
     "est_error_ns", "synchronised", "detail_json"},
    {"losses", "id", "session_id", "channel", "clock", "t_ns", "first_missing", "count", "kind"},
    {"origins", "origin", "event_seq", "clock_sample_id", "loss_id", "rate_block_id", "marker_id"},
    {"origin_sessions", "origin", "origin_session_id", "session_id"},
    {"rate_blocks", "id", "session_id", "channel", "clock", "counts_per_deg_s", "first_index", "count",
     "first_ns", "last_ns", "layout", "samples"},
    {"markers", "id", "session_id", "name", "clock", "t_ns", "source", "uncertainty_ns", "key", "sender_ns",
     "origin"},
    {"event_spans", "id", "session_id", "channel", "clock", "first_seq", "last_seq", "first_ns", "last_ns",
     "count"},
};

}  // namespace

Tables tables_of(sqlite::Database& db) {
  Tables out;
  // One statement for all tables: a prepare per table cost as much as the comparison itself.
  sqlite::Statement columns(db,
                            "SELECT t.name, c.name FROM sqlite_schema t JOIN pragma_table_info(t.name) c "
                            "WHERE t.type = 'table' AND t.name NOT LIKE 'sqlite_%'");
  while (columns.step()) out[std::string(columns.column_text(0))].emplace(columns.column_text(1));
  return out;
}

Tables tables_created_by(std::span<const Migration> steps) {
  auto db = sqlite::Database::open(":memory:", sqlite::Database::Mode::read_write_create);
  for (const auto& step : steps) db.exec(step.sql);
  return tables_of(db);
}

Tables expected_tables(int version) {
  if (version < latest_version())
    return tables_created_by(migrations().first(static_cast<std::size_t>(version)));
  Tables out;
  for (const auto& table : kLatestTables) {
    auto& columns = out[std::string(table[0])];
    for (const auto& column : std::span(table).subspan(1))
      if (!column.empty()) columns.emplace(column);
  }
  return out;
}

std::span<const Migration> migrations() { return kMigrations; }

int latest_version() { return static_cast<int>(kMigrations.size()); }

int identify(sqlite::Database& db, std::span<const Migration> steps) {
  // One read transaction, so the three readings are of one moment: read one by one, a store that
  // another process is creating right now could show its tables but not yet its application_id.
  db.exec("BEGIN");
  std::int64_t application_id = 0, version = 0, objects = 0;
  try {
    application_id = db.query_int("PRAGMA application_id");
    version = db.query_int("PRAGMA user_version");
    objects = db.query_int("SELECT count(*) FROM sqlite_schema");
  } catch (...) {
    db.exec("ROLLBACK");
    throw;
  }
  db.exec("COMMIT");
  if (application_id == 0 && version == 0 && objects == 0) return 0;  // empty: a new store
  if (application_id != kApplicationId) {
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: not an m2mlat store (an SQLite database with application_id {:#x} "
                                  "and {} schema objects)",
                                  db.path(), application_id, objects));
  }
  const auto known = static_cast<std::int64_t>(steps.size());
  if (version > known) {
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: store schema version {} is newer than this m2mlat {} knows (up to {}); "
                    "open it with a newer m2mlat",
                    db.path(), version, core::kVersion, known));
  }
  if (version < 1) {
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: damaged m2mlat store (application_id set, schema version {})", db.path(), version));
  }
  const auto format = db.query_text("SELECT value FROM meta WHERE key = 'format'");
  if (format != kFormatName) {
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: not an m2mlat store (meta format '{}', expected '{}')", db.path(),
                                  format, kFormatName));
  }
  return static_cast<int>(version);
}

void check_tables(sqlite::Database& db, int version) {
  const auto want = expected_tables(version);
  const auto have = tables_of(db);
  for (const auto& [table, columns] : want) {
    const auto found = have.find(table);
    if (found == have.end())
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: damaged m2mlat store (schema version {}): table '{}' is missing",
                                    db.path(), version, table));
    for (const auto& column : columns)
      if (!found->second.contains(column))
        throw core::Error(core::ErrorKind::data,
                          fmt::format("{}: damaged m2mlat store (schema version {}): table '{}' has no "
                                      "column '{}'",
                                      db.path(), version, table, column));
  }
}

int migrate(sqlite::Database& db, std::span<const Migration> steps) {
  const auto known = static_cast<std::int64_t>(steps.size());
  for (;;) {
    sqlite::Transaction transaction(db);
    // Read again under the write lock: another process may have migrated since identify().
    const auto version = db.query_int("PRAGMA user_version");
    if (version > known) {
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("{}: store schema version {} is newer than this m2mlat {} knows (up to {})", db.path(),
                      version, core::kVersion, known));
    }
    if (version == known) {
      transaction.commit();
      return static_cast<int>(version);
    }
    const Migration& step = steps[static_cast<std::size_t>(version)];
    try {
      db.exec(step.sql);
    } catch (const core::Error& e) {
      throw core::Error(core::ErrorKind::internal,
                        fmt::format("{}: migration to schema version {} ({}) failed: {}", db.path(),
                                    version + 1, step.description, e.what()));
    }
    if (version == 0) {
      db.exec(fmt::format("PRAGMA application_id = {}", kApplicationId));
      sqlite::Statement meta(db, "INSERT INTO meta (key, value) VALUES (?1, ?2)");
      meta.bind(1, std::string_view("format"));
      meta.bind(2, kFormatName);
      meta.step();
      meta.reset();
      meta.bind(1, std::string_view("created_by"));
      meta.bind(2, fmt::format("m2mlat {}", core::kVersion));
      meta.step();
    }
    db.exec(fmt::format("PRAGMA user_version = {}", version + 1));
    transaction.commit();
  }
}

}  // namespace m2mlat::store::schema
