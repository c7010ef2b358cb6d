// Opening, writing and reading the store. Hot paths (event insert, resume-by-seq read) use
// statements prepared once per connection; filtered reads build their SQL from the filter.
#include "m2mlat/store/store.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <thread>
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/version.hpp"
#include "m2mlat/store/rows.hpp"
#include "m2mlat/store/schema.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store_impl.hpp"
#include "m2mlat/store/validate.hpp"

namespace m2mlat::store {

namespace {

// Refuses a non-empty file that does not start with SQLite's 16-byte magic, before SQLite sees it.
// (An empty file is a new database; SQLite in WAL mode may leave the main file empty until the
// first checkpoint.)
void check_sqlite_header(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error))
    throw core::Error(core::ErrorKind::data, fmt::format("{}: not an m2mlat store (a directory)", path));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot read: {}", path, std::strerror(errno)));
  constexpr std::string_view kMagic{"SQLite format 3\0", 16};
  std::array<char, 16> head{};
  in.read(head.data(), head.size());
  const auto got = static_cast<std::size_t>(in.gcount());
  if (got == 0) return;
  if (got < head.size() || std::string_view(head.data(), head.size()) != kMagic)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: not an m2mlat store (not an SQLite database)", path));
}

int synchronous_level(Durability durability) {
  switch (durability) {
    case Durability::full: return 2;
    case Durability::normal: return 1;
    case Durability::off: return 0;
  }
  return 1;
}

// The WHERE clause for an event filter over "events e [JOIN sessions s]". Parameters ?1..?3 are
// clock, from, to; the optional ones follow in the order of bind_event_filter.
std::string event_where(const EventFilter& filter) {
  std::string where = "e.clock = ?1 AND e.t_ns BETWEEN ?2 AND ?3";
  if (filter.session_id) where += " AND e.session_id = ?4";
  if (filter.node) where += " AND s.node = ?5";
  if (filter.channel) where += " AND e.channel = ?6";
  if (filter.edge) where += " AND e.edge = ?7";
  return where;
}

void bind_event_filter(sqlite::Statement& query, core::TimePoint from, core::TimePoint to,
                       const EventFilter& filter) {
  query.bind(1, static_cast<std::int64_t>(from.clock()));
  query.bind(2, from.ns());
  query.bind(3, to.ns());
  if (filter.session_id) query.bind(4, *filter.session_id);
  if (filter.node) query.bind(5, *filter.node);
  if (filter.channel) query.bind(6, *filter.channel);
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
  std::error_code error;
  const bool exists = std::filesystem::exists(path, error);
  if (!exists && (options.read_only || !options.create))
    throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such store", path));
  if (exists) check_sqlite_header(path);

  using Mode = sqlite::Database::Mode;
  auto db = sqlite::Database::open(path, options.read_only ? Mode::read_only
                                         : options.create  ? Mode::read_write_create
                                                           : Mode::read_write);
  db.set_busy_timeout(options.busy_timeout_ms);
  const auto steps = schema::migrations();
  int version = schema::identify(db, steps);
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

void Store::end_session(std::int64_t id, core::TimePoint end) {
  impl_->require_writable();
  sqlite::Transaction transaction(impl_->db);
  const auto current = session(id);
  const std::string what = fmt::format("ending session {}", id);
  if (!current) core::throw_data_error({path(), 0}, fmt::format("{}: no such session", what));
  if (current->end) core::throw_data_error({path(), 0}, fmt::format("{}: already ended", what));
  Session ended = *current;
  ended.end = end;
  validate::session(path(), ended);  // same clock as start, not before it
  sqlite::Statement update(impl_->db, "UPDATE sessions SET end_clock = ?2, end_ns = ?3 WHERE id = ?1");
  update.bind(1, id);
  update.bind(2, static_cast<std::int64_t>(end.clock()));
  update.bind(3, end.ns());
  update.step();
  transaction.commit();
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
  sqlite::Statement query(impl_->db,
                          fmt::format("SELECT {} FROM events e JOIN sessions s ON s.id = e.session_id "
                                      "WHERE {} ORDER BY e.t_ns, e.seq",
                                      rows::kEventColumns, event_where(filter)));
  bind_event_filter(query, from, to, filter);
  std::vector<StoredEvent> out;
  while (query.step()) out.push_back(rows::read_event(query, path()));
  return out;
}

Timestamps Store::timestamps(core::TimePoint from, core::TimePoint to, const EventFilter& filter) const {
  require_same_clock(path(), from, to);
  const std::string join = filter.node ? " JOIN sessions s ON s.id = e.session_id" : "";
  sqlite::Statement query(impl_->db, fmt::format("SELECT e.seq, e.t_ns FROM events e{} WHERE {} "
                                                 "ORDER BY e.t_ns, e.seq",
                                                 join, event_where(filter)));
  bind_event_filter(query, from, to, filter);
  Timestamps out;
  out.clock = from.clock();
  while (query.step()) {
    out.seq.push_back(query.column_int64(0));
    out.t_ns.push_back(query.column_int64(1));
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

std::vector<std::string> Store::channels(std::int64_t session_id) const {
  // Answered from the events_by_session index (session_id, channel, ...) without reading events.
  sqlite::Statement query(impl_->db,
                          "SELECT DISTINCT channel FROM events WHERE session_id = ?1 ORDER BY channel");
  query.bind(1, session_id);
  std::vector<std::string> out;
  while (query.step()) out.emplace_back(query.column_text(0));
  return out;
}

std::int64_t Store::last_seq() const {
  return impl_->db.query_int("SELECT coalesce(max(seq), 0) FROM events");
}

std::int64_t Store::event_count(std::optional<std::int64_t> session_id) const {
  if (!session_id) return impl_->db.query_int("SELECT count(*) FROM events");
  sqlite::Statement query(impl_->db, "SELECT count(*) FROM events WHERE session_id = ?1");
  query.bind(1, *session_id);
  return query.step() ? query.column_int64(0) : 0;
}

bool Store::integrity_ok() const {
  if (impl_->db.query_text("PRAGMA integrity_check") != "ok") return false;
  sqlite::Statement dangling(impl_->db, "PRAGMA foreign_key_check");
  return !dangling.step();
}

}  // namespace m2mlat::store
