// Opening, writing and reading the store. Hot paths (event insert, resume-by-seq read) use
// statements prepared once per connection; filtered reads build their SQL from the filter.
#include "m2mlat/store/store.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <stdio.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <thread>
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/core/version.hpp"
#include "m2mlat/store/row_check.hpp"
#include "m2mlat/store/rows.hpp"
#include "m2mlat/store/schema.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store_impl.hpp"
#include "m2mlat/store/validate.hpp"

namespace m2mlat::store {

namespace {

// Refuses a directory or any other non-regular file by stat() alone, which opens nothing. The
// SQLite header itself is checked by SQLite (Database::holds_database), never by opening the file
// here: closing any descriptor of a file drops every POSIX lock this process holds on it, SQLite's
// included, and another process that then opens and closes the store would take it for unused and
// delete the -wal and -shm under this process's connections (committed events lost).
void check_regular_file(const std::string& path, const std::filesystem::file_status& status) {
  namespace fs = std::filesystem;
  if (fs::is_directory(status))
    throw core::Error(core::ErrorKind::data, fmt::format("{}: not an m2mlat store (a directory)", path));
  if (!fs::is_regular_file(status))
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: not an m2mlat store (not a regular file)", path));
}

// Removes a new store's temporary file and whatever SQLite made beside it. unlink() opens nothing.
void remove_new(const std::string& temp) {
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) ::unlink((temp + suffix).c_str());
}

// Creates the store at `path` complete or not at all: the schema is written under a temporary
// name in the same directory (".NAME.<8 hex digits>"), the file is closed (its log checkpointed into it),
// and only then is it renamed to `path`, without replacing a file another process created there
// in the meantime (that one is opened instead). So a failure (a full disk, a signal) leaves nothing
// half-made at `path`; a kill -9 during creation may leave the hidden temporary file.
void create_store(const std::string& path, const Options& options) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Made with open(O_EXCL) and the mode SQLite gives a file it creates (0644 less the umask); mkstemp
  // would make it 0600, unreadable to a dashboard or backup running as another user.
  std::string temp;
  core::Fd fd;
  std::random_device random;
  for (int attempt = 0; !fd && attempt < 100; ++attempt) {
    temp = (dir / fmt::format(".{}.{:08x}", target.filename().string(), random())).string();
    fd.reset(::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644));
    if (!fd && errno != EEXIST) break;
  }
  if (!fd)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: cannot create the store: {}", path, std::strerror(errno)));
  fd.reset();  // a file only this call knows: no connection to it exists
  try {
    auto db = sqlite::Database::open(temp, sqlite::Database::Mode::read_write);
    db.set_busy_timeout(options.busy_timeout_ms);
    // The schema is written in rollback-journal mode, straight into the file; WAL is switched on
    // last (a header change), so closing leaves no log that the rename would separate from it.
    schema::migrate(db, schema::migrations());
    const auto mode = db.query_text("PRAGMA journal_mode = WAL");
    if (mode != "wal")
      throw core::Error(core::ErrorKind::io,
                        fmt::format("{}: cannot switch to WAL journal mode (got '{}')", path, mode));
  } catch (const core::Error& e) {
    remove_new(temp);
    // SQLite names the temporary file; the user knows the store by its own name.
    throw core::Error(e.kind(), fmt::format("{}: cannot create the store: {}", path, e.what()));
  }
  if (::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, path.c_str(), RENAME_NOREPLACE) == 0) {
    remove_new(temp);  // leftovers beside the old name, if any (empty once closed)
    return;
  }
  int failure = errno;
  if (failure == EINVAL) {  // a file system without RENAME_NOREPLACE: link() does not replace either
    failure = ::link(temp.c_str(), path.c_str()) == 0 ? 0 : errno;
  }
  remove_new(temp);
  if (failure != 0 && failure != EEXIST)  // EEXIST: another process created it first; it is opened
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: cannot create the store: {}", path, std::strerror(failure)));
}

int synchronous_level(Durability durability) {
  switch (durability) {
    case Durability::full: return 2;
    case Durability::normal: return 1;
    case Durability::off: return 0;
  }
  return 1;
}

// The spans "b" an event filter selects: those on the clock (?1) that overlap from..to (?2, ?3), of
// the session (?4) and channel (?6) if given; of the node's sessions (?5) if given.
std::string span_where(const EventFilter& filter) {
  std::string sql = "b.clock = ?1 AND b.last_ns >= ?2 AND b.first_ns <= ?3";
  if (filter.session_id) sql += " AND b.session_id = ?4";
  if (filter.channel) sql += " AND b.channel = ?6";
  return sql;
}

// The first seqs of the spans a read of `filter` goes through: what it must check first.
std::string span_select(const EventFilter& filter) {
  std::string sql = "SELECT b.first_seq FROM event_spans b WHERE " + span_where(filter);
  if (filter.node) sql += " AND b.session_id IN (SELECT id FROM sessions WHERE node = ?5)";
  return sql;
}

// The SELECT of `columns` of "events e" (and "sessions s" if `sessions`) that an event filter
// selects. Parameters as in span_where, then the edge (?7). The spans that span_where selects are
// the outer loop (CROSS JOIN keeps SQLite from reordering it), and each span's events are read by
// their seq (rowid) range; an event matches only the span of its own session, channel and clock, so
// none is read twice.
std::string event_select(std::string_view columns, const EventFilter& filter, bool sessions) {
  std::string sql = fmt::format("SELECT {} FROM event_spans b CROSS JOIN events e", columns);
  if (sessions || filter.node) sql += " JOIN sessions s ON s.id = e.session_id";
  sql += " WHERE " + span_where(filter);
  sql += " AND e.seq BETWEEN b.first_seq AND b.last_seq AND e.session_id = b.session_id AND "
         "e.channel = b.channel AND e.clock = ?1 AND e.t_ns BETWEEN ?2 AND ?3";
  if (filter.node) sql += " AND s.node = ?5";
  if (filter.edge) sql += " AND e.edge = ?7";
  // No ORDER BY: the rows come span by span, nearly in time order already, and are put in order
  // (t_ns, seq) by the caller, in memory; SQLite's sort of millions of rows took twice the read.
  return sql;
}

// (t_ns, seq) pairs in order, as ORDER BY e.t_ns, e.seq would give them (seq is unique: no ties).
void order_by_time(std::vector<std::pair<std::int64_t, std::int64_t>>& keys) {
  if (!std::is_sorted(keys.begin(), keys.end())) std::sort(keys.begin(), keys.end());
}

// Binds span_select's parameters (?1 to ?6).
void bind_span_filter(sqlite::Statement& query, core::TimePoint from, core::TimePoint to,
                      const EventFilter& filter) {
  query.bind(1, static_cast<std::int64_t>(from.clock()));
  query.bind(2, from.ns());
  query.bind(3, to.ns());
  if (filter.session_id) query.bind(4, *filter.session_id);
  if (filter.node) query.bind(5, *filter.node);
  if (filter.channel) query.bind(6, *filter.channel);
}

// Binds event_select's parameters.
void bind_event_filter(sqlite::Statement& query, core::TimePoint from, core::TimePoint to,
                       const EventFilter& filter) {
  bind_span_filter(query, from, to, filter);
  if (filter.edge) query.bind(7, static_cast<std::int64_t>(*filter.edge));
}

void require_same_clock(const std::string& path, core::TimePoint from, core::TimePoint to) {
  if (from.clock() != to.clock())
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{}: time range from clock {} to clock {}: both ends must be on one clock",
                                  path, core::to_string(from.clock()), core::to_string(to.clock())));
}

std::int64_t limit_column(std::size_t limit) {
  constexpr auto kMax = static_cast<std::size_t>(std::numeric_limits<std::int64_t>::max());
  return static_cast<std::int64_t>(std::min(limit, kMax));
}

// Switching a new database to WAL needs it to itself, and SQLite's busy handler does not wait for
// that: two processes opening the same new store at once (two recorders into one file) would see
// one of them fail with "database is locked". Retry until the busy timeout (milliseconds) instead.
std::string switch_to_wal(sqlite::Database& db, int busy_timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(busy_timeout_ms);
  for (;;) {
    try {
      return db.query_text("PRAGMA journal_mode = WAL");
    } catch (const core::Error&) {
      if (!db.last_error_was_busy() || std::chrono::steady_clock::now() >= deadline) throw;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace

Store::Store(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Store::Store(Store&&) noexcept = default;
Store& Store::operator=(Store&&) noexcept = default;
Store::~Store() = default;

Store Store::open(const std::string& path, const Options& options) {
  namespace fs = std::filesystem;
  std::error_code error;
  auto status = fs::status(path, error);  // stat(): opens nothing
  if (error && status.type() != fs::file_type::not_found)
    throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot read: {}", path, error.message()));
  if (!fs::exists(status)) {
    if (options.read_only || !options.create)
      throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such store", path));
    create_store(path, options);
    status = fs::status(path, error);
  }
  check_regular_file(path, status);

  using Mode = sqlite::Database::Mode;
  auto db = sqlite::Database::open(path, options.read_only ? Mode::read_only : Mode::read_write);
  db.set_busy_timeout(options.busy_timeout_ms);
  if (!db.holds_database())
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: not an m2mlat store (not an SQLite database)", path));
  const auto steps = schema::migrations();
  int version = schema::identify(db, steps);
  if (version > 0) schema::check_tables(db, version);
  if (options.read_only) {
    if (version == 0)
      throw core::Error(core::ErrorKind::data,
                        fmt::format("{}: not an m2mlat store (an empty database)", path));
    if (version < schema::latest_version())
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("{}: store schema version {} is older than this m2mlat's ({}); open it once "
                      "for writing to upgrade it",
                      path, version, schema::latest_version()));
  } else {
    // WAL: readers do not block the writer, and a commit is one append to the log, so a crash in
    // the middle of a batch leaves the database file as it was.
    const auto mode = switch_to_wal(db, options.busy_timeout_ms);
    if (mode != "wal")
      throw core::Error(core::ErrorKind::io,
                        fmt::format("{}: cannot switch to WAL journal mode (got '{}')", path, mode));
    db.exec(fmt::format("PRAGMA synchronous = {}", synchronous_level(options.durability)));
    db.exec("PRAGMA foreign_keys = ON");
    version = schema::migrate(db, steps);
  }
  return Store(std::make_unique<Impl>(std::move(db), options, version));
}

const std::string& Store::path() const { return impl_->db.path(); }
int Store::schema_version() const { return impl_->version; }

std::string Store::created_by() const {
  return impl_->db.query_text("SELECT value FROM meta WHERE key = 'created_by'");
}
std::string Store::store_id() const {
  return impl_->db.query_text("SELECT value FROM meta WHERE key = 'store_id'");
}
std::string Store::journal_mode() const { return impl_->db.query_text("PRAGMA journal_mode"); }
int Store::synchronous() const { return static_cast<int>(impl_->db.query_int("PRAGMA synchronous")); }

// --- sessions -----------------------------------------------------------------------------------

std::int64_t Store::begin_session(const Session& session) {
  impl_->require_writable();
  validate::session(path(), session);
  Session row = session;
  if (row.software_version.empty()) row.software_version = core::kVersion;
  sqlite::Statement insert(impl_->db, rows::kInsertSession);
  rows::bind_session(insert, row);
  insert.step();
  return impl_->db.last_insert_rowid();
}

void Store::end_session(std::int64_t id, core::TimePoint end, const std::optional<std::string>& config_json) {
  impl_->require_writable();
  sqlite::Transaction transaction(impl_->db);
  const auto current = session(id);
  const std::string what = fmt::format("ending session {}", id);
  if (!current) core::throw_data_error({path(), 0}, fmt::format("{}: no such session", what));
  if (current->end) core::throw_data_error({path(), 0}, fmt::format("{}: already ended", what));
  Session ended = *current;
  ended.end = end;
  if (config_json) ended.config_json = *config_json;
  validate::session(path(), ended);  // same clock as start, not before it; the configuration is JSON
  sqlite::Statement update(impl_->db,
                           "UPDATE sessions SET end_clock = ?2, end_ns = ?3, config_json = ?4 WHERE id = ?1");
  update.bind(1, id);
  update.bind(2, static_cast<std::int64_t>(end.clock()));
  update.bind(3, end.ns());
  update.bind(4, ended.config_json);
  update.step();
  transaction.commit();
}

std::vector<Session> Store::close_cut_sessions(const std::string& node, core::TimePoint now) {
  impl_->require_writable();
  sqlite::Transaction transaction(impl_->db);
  std::vector<std::int64_t> open;
  {
    sqlite::Statement query(impl_->db,
                            "SELECT id FROM sessions WHERE node = ?1 AND end_ns IS NULL ORDER BY id");
    query.bind(1, node);
    while (query.step()) open.push_back(query.column_int64(0));
  }
  std::vector<Session> cut;
  for (const std::int64_t id : open) {
    // The latest time the session is known to have been alive, on its start's clock (ns).
    sqlite::Statement last(
        impl_->db,
        "SELECT max(s.start_ns, coalesce((SELECT max(last_ns) FROM event_spans WHERE session_id = s.id "
        "AND clock = s.start_clock), s.start_ns), coalesce((SELECT max(t_ns) FROM "
        "clock_samples WHERE session_id = s.id AND clock = s.start_clock), s.start_ns)), "
        "coalesce((SELECT max(last_seq) FROM event_spans WHERE session_id = s.id), 0) "
        "FROM sessions s WHERE s.id = ?1");
    last.bind(1, id);
    last.step();
    const std::int64_t end_ns = last.column_int64(0);
    const std::int64_t last_seq = last.column_int64(1);
    Loss loss;
    loss.session_id = id;
    loss.detected_at = now;
    loss.first_missing = static_cast<std::uint64_t>(last_seq + 1);
    loss.count = 1;
    loss.kind = "restart";
    rows::bind_loss(impl_->insert_loss, loss);
    impl_->insert_loss.step();
    impl_->insert_loss.reset();
    sqlite::Statement update(impl_->db,
                             "UPDATE sessions SET end_clock = start_clock, end_ns = ?2 WHERE id = ?1");
    update.bind(1, id);
    update.bind(2, end_ns);
    update.step();
    cut.push_back(*session(id));
  }
  transaction.commit();
  return cut;
}

std::vector<Session> Store::sessions() const {
  sqlite::Statement query(impl_->db,
                          fmt::format("SELECT {} FROM sessions ORDER BY id", rows::kSessionColumns));
  std::vector<Session> out;
  while (query.step()) out.push_back(rows::read_session(query, path()));
  return out;
}

std::optional<Session> Store::session(std::int64_t id) const {
  sqlite::Statement query(impl_->db,
                          fmt::format("SELECT {} FROM sessions WHERE id = ?1", rows::kSessionColumns));
  query.bind(1, id);
  if (!query.step()) return std::nullopt;
  return rows::read_session(query, path());
}

// --- appends ------------------------------------------------------------------------------------

AppendResult Store::append(const Batch& batch) {
  Impl& s = *impl_;
  s.require_writable();
  // Check every value before the transaction, so that a bad one is reported without any write.
  for (std::size_t i = 0; i < batch.events.size(); ++i) validate::event(path(), i, batch.events[i]);
  for (std::size_t i = 0; i < batch.losses.size(); ++i) validate::loss(path(), i, batch.losses[i]);
  for (std::size_t i = 0; i < batch.clock_samples.size(); ++i)
    validate::clock_sample(path(), i, batch.clock_samples[i]);
  for (std::size_t i = 0; i < batch.rate_blocks.size(); ++i)
    validate::rate_block(path(), i, batch.rate_blocks[i]);
  for (std::size_t i = 0; i < batch.markers.size(); ++i) validate::marker(path(), i, batch.markers[i]);

  sqlite::Transaction transaction(s.db);
  AppendResult result;
  if (!batch.events.empty()) {
    const std::string node = s.require_open_session(batch.session_id, "appending events");
    const std::size_t n = batch.events.size();
    for (std::size_t i = 0; i < n; ++i)
      if (batch.events[i].node != node)
        core::throw_data_error({path(), 0},
                               fmt::format("event {} of the batch: field 'node' is '{}', but session {} "
                                           "records node '{}'",
                                           i, batch.events[i].node, batch.session_id, node));
    // Blocks of kEventsPerInsert rows per statement, the rest one by one. Within the transaction (the
    // write lock held) each row's seq is the largest so far plus one, so a block's are consecutive.
    constexpr auto block = static_cast<std::size_t>(rows::kEventsPerInsert);
    std::size_t i = 0;
    for (; n - i >= block; i += block) {
      for (std::size_t k = 0; k < block; ++k)
        rows::bind_event(s.insert_events, batch.session_id, batch.events[i + k], static_cast<int>(k) * 8);
      s.insert_events.step();
      s.insert_events.reset();
      if (i == 0) result.first_seq = s.db.last_insert_rowid() - static_cast<std::int64_t>(block - 1);
    }
    for (; i < n; ++i) {
      rows::bind_event(s.insert_event, batch.session_id, batch.events[i]);
      s.insert_event.step();
      s.insert_event.reset();
      if (i == 0) result.first_seq = s.db.last_insert_rowid();
    }
    result.last_seq = s.db.last_insert_rowid();
    // The batch's seqs are consecutive (above): event k has first_seq + k.
    event_spans::SpanBuilder spans;
    for (std::size_t k = 0; k < n; ++k) {
      const core::Event& e = batch.events[k];
      spans.add(result.first_seq + static_cast<std::int64_t>(k), batch.session_id, e.channel, e.time.clock(),
                  e.time.ns());
    }
    spans.write(s.insert_span);
  }
  std::set<std::int64_t> checked;
  for (const Loss& loss : batch.losses) {
    if (checked.insert(loss.session_id).second) s.require_open_session(loss.session_id, "appending losses");
    rows::bind_loss(s.insert_loss, loss);
    s.insert_loss.step();
    s.insert_loss.reset();
  }
  for (const ClockSample& sample : batch.clock_samples) {
    if (checked.insert(sample.session_id).second)
      s.require_open_session(sample.session_id, "appending clock samples");
    rows::bind_clock_sample(s.insert_clock_sample, sample);
    s.insert_clock_sample.step();
    s.insert_clock_sample.reset();
  }
  for (const RateBlock& block : batch.rate_blocks) {
    if (checked.insert(block.session_id).second)
      s.require_open_session(block.session_id, "appending raw rate samples");
    rows::bind_rate_block(s.insert_rate_block, block);
    s.insert_rate_block.step();
    s.insert_rate_block.reset();
  }
  for (const MarkerRecord& marker : batch.markers) {
    if (checked.insert(marker.session_id).second) s.require_open_session(marker.session_id, "appending markers");
    rows::bind_marker(s.insert_marker, marker);
    s.insert_marker.step();
    s.insert_marker.reset();
  }
  transaction.commit();
  return result;
}

std::int64_t Store::append_events(std::int64_t session_id, std::span<const core::Event> events) {
  Batch batch;
  batch.session_id = session_id;
  batch.events.assign(events.begin(), events.end());
  return append(batch).first_seq;
}

void Store::append_clock_samples(std::span<const ClockSample> samples) {
  Batch batch;
  batch.clock_samples.assign(samples.begin(), samples.end());
  append(batch);
}

void Store::append_losses(std::span<const Loss> losses) {
  Batch batch;
  batch.losses.assign(losses.begin(), losses.end());
  append(batch);
}

void Store::append_rate_blocks(std::span<const RateBlock> blocks) {
  Batch batch;
  batch.rate_blocks.assign(blocks.begin(), blocks.end());
  append(batch);
}

void Store::append_markers(std::span<const MarkerRecord> markers) {
  Batch batch;
  batch.markers.assign(markers.begin(), markers.end());
  append(batch);
}

// --- reads --------------------------------------------------------------------------------------

std::vector<StoredEvent> Store::events_after(std::int64_t after_seq, std::size_t limit) const {
  sqlite::Statement& query = impl_->events_after;
  ResetOnExit done(query);
  query.bind(1, after_seq);
  query.bind(2, limit_column(limit));
  std::vector<StoredEvent> out;
  while (query.step()) out.push_back(rows::read_event(query, path()));
  return out;
}

std::vector<StoredEvent> Store::events_in_time(core::TimePoint from, core::TimePoint to,
                                               const EventFilter& filter) const {
  require_same_clock(path(), from, to);
  ReadTransaction snapshot(impl_->db);
  impl_->check_read(from, to, filter);
  sqlite::Statement query(impl_->db, event_select(rows::kEventColumns, filter, true));
  bind_event_filter(query, from, to, filter);
  std::vector<StoredEvent> read;
  while (query.step()) read.push_back(rows::read_event(query, path()));
  // Ordered through ((t_ns, seq), index) keys: moving the events themselves (two strings each)
  // costs more.
  std::vector<std::pair<std::pair<std::int64_t, std::int64_t>, std::size_t>> order(read.size());
  for (std::size_t i = 0; i < read.size(); ++i) order[i] = {{read[i].event.time.ns(), read[i].seq}, i};
  if (std::is_sorted(order.begin(), order.end())) return read;
  std::sort(order.begin(), order.end());
  std::vector<StoredEvent> out;
  out.reserve(read.size());
  for (const auto& entry : order) out.push_back(std::move(read[entry.second]));
  return out;
}

Timestamps Store::timestamps(core::TimePoint from, core::TimePoint to, const EventFilter& filter) const {
  require_same_clock(path(), from, to);
  ReadTransaction snapshot(impl_->db);
  impl_->check_read(from, to, filter);
  sqlite::Statement query(impl_->db, event_select("e.t_ns, e.seq", filter, false));
  bind_event_filter(query, from, to, filter);
  std::vector<std::pair<std::int64_t, std::int64_t>> keys;  // (t_ns, seq)
  while (query.step()) keys.emplace_back(query.column_int64(0), query.column_int64(1));
  order_by_time(keys);
  Timestamps out;
  out.clock = from.clock();
  out.seq.reserve(keys.size());
  out.t_ns.reserve(keys.size());
  for (const auto& [t_ns, seq] : keys) {
    out.seq.push_back(seq);
    out.t_ns.push_back(t_ns);
  }
  return out;
}

std::vector<ClockSample> Store::clock_samples(std::optional<std::int64_t> session_id) const {
  std::string sql = fmt::format("SELECT {} FROM clock_samples", rows::kClockSampleColumns);
  if (session_id) sql += " WHERE session_id = ?1";
  sql += " ORDER BY clock, t_ns, id";
  sqlite::Statement query(impl_->db, sql);
  if (session_id) query.bind(1, *session_id);
  std::vector<ClockSample> out;
  while (query.step()) out.push_back(rows::read_clock_sample(query, path()));
  return out;
}

std::vector<ClockSample> Store::clock_samples(std::optional<std::int64_t> session_id, core::TimePoint from,
                                              core::TimePoint to) const {
  require_same_clock(path(), from, to);
  std::string sql = fmt::format("SELECT {} FROM clock_samples WHERE clock = ?2 AND t_ns BETWEEN ?3 AND ?4",
                                rows::kClockSampleColumns);
  if (session_id) sql += " AND session_id = ?1";
  sql += " ORDER BY t_ns, id";
  sqlite::Statement query(impl_->db, sql);
  if (session_id) query.bind(1, *session_id);
  query.bind(2, static_cast<std::int64_t>(from.clock()));
  query.bind(3, from.ns());
  query.bind(4, to.ns());
  std::vector<ClockSample> out;
  while (query.step()) out.push_back(rows::read_clock_sample(query, path()));
  return out;
}

std::vector<Loss> Store::losses(std::optional<std::int64_t> session_id) const {
  std::string sql = fmt::format("SELECT {} FROM losses", rows::kLossColumns);
  if (session_id) sql += " WHERE session_id = ?1";
  sql += " ORDER BY id";
  sqlite::Statement query(impl_->db, sql);
  if (session_id) query.bind(1, *session_id);
  std::vector<Loss> out;
  while (query.step()) out.push_back(rows::read_loss(query, path()));
  return out;
}

std::vector<StoredClockSample> Store::clock_samples_after(std::int64_t after_id, std::size_t limit) const {
  // The row id is selected last, after the columns read_clock_sample expects from position 0.
  sqlite::Statement query(impl_->db, fmt::format("SELECT {}, id FROM clock_samples WHERE id > ?1 "
                                                 "ORDER BY id LIMIT ?2",
                                                 rows::kClockSampleColumns));
  query.bind(1, after_id);
  query.bind(2, limit_column(limit));
  std::vector<StoredClockSample> out;
  while (query.step()) out.push_back({query.column_int64(9), rows::read_clock_sample(query, path())});
  return out;
}

std::vector<StoredLoss> Store::losses_after(std::int64_t after_id, std::size_t limit) const {
  sqlite::Statement query(
      impl_->db,
      fmt::format("SELECT {}, id FROM losses WHERE id > ?1 ORDER BY id LIMIT ?2", rows::kLossColumns));
  query.bind(1, after_id);
  query.bind(2, limit_column(limit));
  std::vector<StoredLoss> out;
  while (query.step()) out.push_back({query.column_int64(7), rows::read_loss(query, path())});
  return out;
}

std::vector<RateChannel> Store::rate_channels() const {
  sqlite::Statement query(impl_->db,
                          "SELECT b.session_id, s.node, b.channel, sum(b.count) FROM rate_blocks b "
                          "JOIN sessions s ON s.id = b.session_id GROUP BY b.session_id, b.channel "
                          "ORDER BY b.session_id, b.channel");
  std::vector<RateChannel> out;
  while (query.step())
    out.push_back({query.column_int64(0), std::string(query.column_text(1)), std::string(query.column_text(2)),
                   query.column_int64(3)});
  return out;
}

core::RateTrace Store::rate_trace(std::int64_t session_id, const std::string& channel) const {
  return rate_trace_tail(session_id, channel, std::numeric_limits<std::int64_t>::max());
}

core::RateTrace Store::rate_trace_tail(std::int64_t session_id, const std::string& channel,
                                       std::int64_t tail_ns) const {
  // The newest stamp less tail_ns, saturated (the whole trace for a tail beyond its start).
  constexpr std::string_view kBlocksOfTail =
      "FROM rate_blocks WHERE session_id = ?1 AND channel = ?2 AND last_ns >= "
      "(SELECT CASE WHEN MAX(last_ns) < -9223372036854775807 + ?3 THEN "
      "-9223372036854775807 - 1 ELSE MAX(last_ns) - ?3 END FROM rate_blocks WHERE "
      "session_id = ?1 AND channel = ?2)";
  const auto bind = [&](sqlite::Statement& q) {
    q.bind(1, session_id);
    q.bind(2, channel);
    q.bind(3, std::max<std::int64_t>(tail_ns, 0));
  };
  core::RateTrace trace;
  {
    // The samples' number first, so that the trace is allocated once: an hour at 8 kHz is 29 million
    // samples (690 MB), and growing by doubling would hold up to twice that while it copies.
    sqlite::Statement total(impl_->db, fmt::format("SELECT TOTAL(count) {}", kBlocksOfTail));
    bind(total);
    // (A file edited by another tool may state counts its BLOBs do not hold: only a plausible total
    // is reserved, and the BLOBs' own lengths are checked as each block is read.)
    if (total.step())
      if (const double n = total.column_double(0); n > 0 && n <= 4e9) trace.samples.reserve(static_cast<std::size_t>(n));
  }
  sqlite::Statement query(impl_->db, fmt::format("SELECT {} {} ORDER BY first_ns, first_index, id",
                                                 rows::kRateBlockColumns, kBlocksOfTail));
  bind(query);
  std::optional<std::int64_t> first_id;
  while (query.step()) {
    StoredRateBlock stored = rows::read_rate_block(query, path());
    const RateBlock& block = stored.block;
    if (!first_id) {
      first_id = stored.id;
      trace.clock = block.clock;
      trace.counts_per_deg_s = block.counts_per_deg_s;
    } else if (block.clock != trace.clock || block.counts_per_deg_s != trace.counts_per_deg_s) {
      core::throw_data_error({path(), 0},
                             fmt::format("table 'rate_blocks' row id {}: its clock or counts_per_deg_s ({}) "
                                         "differs from row id {} of the same trace ({})",
                                         stored.id, block.counts_per_deg_s, *first_id, trace.counts_per_deg_s));
    }
    trace.samples.insert(trace.samples.end(), block.samples.begin(), block.samples.end());
  }
  if (!first_id)
    throw core::Error(core::ErrorKind::no_input,
                      fmt::format("{}: session {} has no raw rate samples on channel '{}'", path(), session_id,
                                  channel));
  // Blocks are ordered by their first stamp; a block overlapping the next (two samplers writing one
  // channel) would leave the trace out of order: order it, ties kept as stored. Checked first: the
  // sort's buffer would be as large as the trace, and a trace is nearly always in order already.
  if (!std::is_sorted(trace.samples.begin(), trace.samples.end(),
                      [](const core::RateSample& a, const core::RateSample& b) { return a.time_ns < b.time_ns; }))
    std::stable_sort(trace.samples.begin(), trace.samples.end(),
                   [](const core::RateSample& a, const core::RateSample& b) { return a.time_ns < b.time_ns; });
  return trace;
}

std::vector<StoredRateBlock> Store::rate_blocks_after(std::int64_t after_id, std::size_t limit) const {
  sqlite::Statement query(impl_->db, fmt::format("SELECT {} FROM rate_blocks WHERE id > ?1 ORDER BY id "
                                                 "LIMIT ?2",
                                                 rows::kRateBlockColumns));
  query.bind(1, after_id);
  query.bind(2, limit_column(limit));
  std::vector<StoredRateBlock> out;
  while (query.step()) out.push_back(rows::read_rate_block(query, path()));
  return out;
}

std::vector<StoredMarker> Store::markers_after(std::int64_t after_id, std::size_t limit) const {
  sqlite::Statement query(impl_->db, fmt::format("SELECT {} FROM markers WHERE id > ?1 ORDER BY id LIMIT ?2",
                                                 rows::kMarkerColumns));
  query.bind(1, after_id);
  query.bind(2, limit_column(limit));
  std::vector<StoredMarker> out;
  while (query.step()) out.push_back(rows::read_marker(query, path()));
  return out;
}

std::vector<StoredMarker> Store::markers(std::optional<std::int64_t> session_id) const {
  sqlite::Statement query(impl_->db,
                          fmt::format("SELECT {} FROM markers WHERE ?1 IS NULL OR session_id = ?1 "
                                      "ORDER BY clock, t_ns, id",
                                      rows::kMarkerColumns));
  if (session_id) query.bind(1, *session_id);
  else query.bind_null(1);
  std::vector<StoredMarker> out;
  while (query.step()) out.push_back(rows::read_marker(query, path()));
  return out;
}

std::vector<std::string> Store::channels(std::int64_t session_id) const {
  // Answered from the spans' index (session_id, channel, ...) without reading events.
  sqlite::Statement query(impl_->db,
                          "SELECT DISTINCT channel FROM event_spans WHERE session_id = ?1 ORDER BY channel");
  query.bind(1, session_id);
  std::vector<std::string> out;
  while (query.step()) out.emplace_back(query.column_text(0));
  return out;
}

std::int64_t Store::last_seq() const {
  return impl_->db.query_int("SELECT coalesce(max(seq), 0) FROM events");
}

std::int64_t Store::event_count(std::optional<std::int64_t> session_id) const {
  // From the spans, which count every event once: a few rows a batch instead of every event.
  if (!session_id) return impl_->db.query_int("SELECT coalesce(sum(count), 0) FROM event_spans");
  sqlite::Statement query(impl_->db,
                          "SELECT coalesce(sum(count), 0) FROM event_spans WHERE session_id = ?1");
  query.bind(1, *session_id);
  return query.step() ? query.column_int64(0) : 0;
}

void Store::check_rows() const {
  ReadTransaction snapshot(impl_->db);  // the tables as of one moment
  row_check::check_tables(impl_->db);   // again if a read checked them: rows may have changed since
  impl_->tables_checked = true;
  impl_->ranges().check_all();
}

event_ranges::Checked& Store::Impl::ranges() {
  if (!checked) checked.emplace(db);
  checked->refresh();
  return *checked;
}

void Store::Impl::check_read(core::TimePoint from, core::TimePoint to, const EventFilter& filter) {
  if (!tables_checked) {
    row_check::check_tables(db);
    tables_checked = true;
  }
  auto& ranges_read = ranges();
  sqlite::Statement spans(db, span_select(filter));
  bind_span_filter(spans, from, to, filter);
  std::vector<std::int64_t> first_seqs;
  while (spans.step()) first_seqs.push_back(spans.column_int64(0));
  ranges_read.check(first_seqs);
}

bool Store::integrity_ok() const {
  if (impl_->db.query_text("PRAGMA integrity_check") != "ok") return false;
  sqlite::Statement dangling(impl_->db, "PRAGMA foreign_key_check");
  return !dangling.step();
}

bool is_sqlite_database(const std::string& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (error || !std::filesystem::is_regular_file(status)) return false;
  const auto size = std::filesystem::file_size(path, error);  // stat() again: opens nothing
  if (error || size == 0) return false;                        // an empty file is no store yet
  try {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
    return db.holds_database();
  } catch (const core::Error&) {
    return false;  // unreadable: the caller's own open reports why
  }
}

void remove_store_files(const std::string& path) { remove_new(path); }

struct WholeWrite::Impl {
  explicit Impl(sqlite::Database& db) : transaction(db) {}
  sqlite::Transaction transaction;
};

WholeWrite::WholeWrite(Store& store) : impl_(std::make_unique<Impl>(store.impl_->db)) {}
WholeWrite::~WholeWrite() = default;
void WholeWrite::commit() { impl_->transaction.commit(); }

}  // namespace m2mlat::store
