// The SQLite C API behind the RAII types, and the mapping of SQLite result codes to error kinds.
#include "m2mlat/store/sqlite.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <cstdint>
#include <utility>

#include "m2mlat/core/error.hpp"

namespace m2mlat::store::sqlite {

namespace {

// SQLITE_TRANSIENT spelled without its old-style cast: SQLite copies the bound text.
const sqlite3_destructor_type kTransient = reinterpret_cast<sqlite3_destructor_type>(std::intptr_t{-1});

core::ErrorKind kind_of(int rc) {
  switch (rc & 0xff) {  // primary result code
    case SQLITE_CONSTRAINT:
    case SQLITE_NOTADB:
    case SQLITE_CORRUPT:
    case SQLITE_MISMATCH:
    case SQLITE_TOOBIG: return core::ErrorKind::data;
    case SQLITE_IOERR:
    case SQLITE_FULL:
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_READONLY:
    case SQLITE_PERM:
    case SQLITE_CANTOPEN:
    case SQLITE_NOLFS:
    case SQLITE_PROTOCOL:
    case SQLITE_NOMEM: return core::ErrorKind::io;
    default: return core::ErrorKind::internal;
  }
}

}  // namespace

void throw_error(sqlite3* db, int rc, std::string_view context) {
  std::string file = "<sqlite>";
  std::string message = sqlite3_errstr(rc);
  if (db != nullptr) {
    if (const char* name = sqlite3_db_filename(db, "main"); name != nullptr && *name != '\0') file = name;
    // The connection's message is more specific than the code's ("UNIQUE constraint failed: ...").
    if (sqlite3_extended_errcode(db) == rc) message = sqlite3_errmsg(db);
  }
  throw core::Error(kind_of(rc), fmt::format("{}: {}: {}", file, context, message));
}

// --- Database -----------------------------------------------------------------------------------

Database Database::open(const std::string& path, Mode mode) {
  int flags = SQLITE_OPEN_NOMUTEX;  // one connection per thread; the store is not shared between threads
  switch (mode) {
    case Mode::read_only: flags |= SQLITE_OPEN_READONLY; break;
    case Mode::read_write: flags |= SQLITE_OPEN_READWRITE; break;
    case Mode::read_write_create: flags |= SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE; break;
  }
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, flags, nullptr);
  if (rc != SQLITE_OK) {
    // sqlite3_open_v2 allocates a handle even on failure; take its message, then free it.
    const std::string message = db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    sqlite3_close_v2(db);
    throw core::Error(kind_of(rc), fmt::format("{}: cannot open: {}", path, message));
  }
  sqlite3_extended_result_codes(db, 1);
  return Database(db, path);
}

Database::Database(Database&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)), path_(std::move(other.path_)) {}

Database& Database::operator=(Database&& other) noexcept {
  if (this != &other) {
    sqlite3_close_v2(db_);
    db_ = std::exchange(other.db_, nullptr);
    path_ = std::move(other.path_);
  }
  return *this;
}

// sqlite3_close_v2 defers the close until the last statement is finalized, so the order in which an
// owner destroys its Database and Statements does not matter.
Database::~Database() { sqlite3_close_v2(db_); }

void Database::exec(std::string_view sql) {
  const std::string text(sql);
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &message);
  sqlite3_free(message);  // the same text is available from sqlite3_errmsg
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("'{}'", sql.substr(0, 60)));
}

bool Database::last_error_was_busy() const {
  const int primary = sqlite3_errcode(db_) & 0xff;
  return primary == SQLITE_BUSY || primary == SQLITE_LOCKED;
}

bool Database::holds_database() {
  sqlite3_stmt* stmt = nullptr;
  int rc = sqlite3_prepare_v2(db_, "PRAGMA schema_version", -1, &stmt, nullptr);
  if (rc == SQLITE_OK) {
    rc = sqlite3_step(stmt);
    sqlite3_finalize(stmt);
  }
  if (rc == SQLITE_ROW || rc == SQLITE_DONE) return true;
  if ((rc & 0xff) == SQLITE_NOTADB) return false;
  throw_error(db_, rc, "reading the database header");
}

std::int64_t Database::query_int(std::string_view sql) {
  Statement statement(*this, sql);
  return statement.step() ? statement.column_int64(0) : 0;
}

std::string Database::query_text(std::string_view sql) {
  Statement statement(*this, sql);
  return statement.step() ? std::string(statement.column_text(0)) : std::string();
}

void Database::set_busy_timeout(int milliseconds) {
  const int rc = sqlite3_busy_timeout(db_, milliseconds);
  if (rc != SQLITE_OK) throw_error(db_, rc, "setting the busy timeout");
}

bool Database::in_transaction() const { return sqlite3_get_autocommit(db_) == 0; }

std::int64_t Database::changes() const { return sqlite3_changes64(db_); }

std::int64_t Database::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

// --- Statement ----------------------------------------------------------------------------------

Statement::Statement(const Database& db, std::string_view sql) : db_(db.handle()) {
  const int rc = sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT,
                                    &stmt_, nullptr);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("preparing '{}'", sql.substr(0, 60)));
}

Statement::Statement(Statement&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)), stmt_(std::exchange(other.stmt_, nullptr)) {}

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    db_ = std::exchange(other.db_, nullptr);
    stmt_ = std::exchange(other.stmt_, nullptr);
  }
  return *this;
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

void Statement::bind(int index, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, index, value);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("binding parameter {}", index));
}

void Statement::bind(int index, std::string_view text) {
  const int rc = sqlite3_bind_text64(stmt_, index, text.data(), text.size(), kTransient, SQLITE_UTF8);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("binding parameter {}", index));
}

void Statement::bind_null(int index) {
  const int rc = sqlite3_bind_null(stmt_, index);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("binding parameter {}", index));
}

void Statement::bind_double(int index, double value) {
  const int rc = sqlite3_bind_double(stmt_, index, value);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("binding parameter {}", index));
}

void Statement::bind_blob(int index, std::span<const std::uint8_t> bytes) {
  const int rc = sqlite3_bind_blob64(stmt_, index, bytes.data(), bytes.size(), kTransient);
  if (rc != SQLITE_OK) throw_error(db_, rc, fmt::format("binding parameter {}", index));
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  // Reset now so that the statement releases its locks; the error stays in the connection.
  sqlite3_reset(stmt_);
  const char* sql = sqlite3_sql(stmt_);
  throw_error(db_, rc,
              fmt::format("running '{}'", std::string_view(sql != nullptr ? sql : "").substr(0, 60)));
}

void Statement::reset() { sqlite3_reset(stmt_); }

std::int64_t Statement::column_int64(int column) const { return sqlite3_column_int64(stmt_, column); }

std::string_view Statement::column_text(int column) const {
  const unsigned char* text = sqlite3_column_text(stmt_, column);
  if (text == nullptr) return {};
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return {reinterpret_cast<const char*>(text), static_cast<std::size_t>(bytes)};
}

bool Statement::column_is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

double Statement::column_double(int column) const { return sqlite3_column_double(stmt_, column); }

std::span<const std::uint8_t> Statement::column_blob(int column) const {
  const void* data = sqlite3_column_blob(stmt_, column);
  if (data == nullptr) return {};
  const int bytes = sqlite3_column_bytes(stmt_, column);
  return {static_cast<const std::uint8_t*>(data), static_cast<std::size_t>(bytes)};
}

// --- Transaction --------------------------------------------------------------------------------

Transaction::Transaction(Database& db) : db_(db), nested_(db.in_transaction()) {
  db_.exec(nested_ ? "SAVEPOINT m2mlat_write" : "BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
  if (!done_ && db_.in_transaction()) {
    // Nothing useful can be done if ROLLBACK itself fails; SQLite rolls back on close anyway.
    sqlite3_exec(db_.handle(), nested_ ? "ROLLBACK TO m2mlat_write; RELEASE m2mlat_write" : "ROLLBACK", nullptr,
                 nullptr, nullptr);
  }
}

void Transaction::commit() {
  db_.exec(nested_ ? "RELEASE m2mlat_write" : "COMMIT");
  done_ = true;
}

}  // namespace m2mlat::store::sqlite
