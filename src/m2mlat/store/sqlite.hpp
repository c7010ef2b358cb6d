// RAII types over the SQLite C API: a connection (Database), a prepared Statement and a
// Transaction guard. Only what the store needs, kept small and explicit; no other wrapper library.
//
// Every failure becomes core::Error naming the database file, what was being done and SQLite's own
// message. The error kind follows SQLite's result code: a violated constraint or a file that is not
// a database is bad data; I/O, locking and permission failures are io; misuse is a bug (internal).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>

struct sqlite3;
struct sqlite3_stmt;

namespace m2mlat::store::sqlite {

// Throws core::Error for result code `rc` on connection `db` (may be null), naming the file.
[[noreturn]] void throw_error(sqlite3* db, int rc, std::string_view context);

class Database {
 public:
  enum class Mode { read_only, read_write, read_write_create };

  // Opens (or creates) the file; the handle uses extended result codes. Throws core::Error(io).
  static Database open(const std::string& path, Mode mode);

  Database(Database&& other) noexcept;
  Database& operator=(Database&& other) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  ~Database();

  // Runs SQL text of one or more statements that return no rows we need (DDL, PRAGMA, BEGIN).
  void exec(std::string_view sql);
  // Runs a query of one row and one integer column (e.g. "PRAGMA user_version"); 0 if no row.
  std::int64_t query_int(std::string_view sql);
  // Same for one text column; empty if no row or NULL.
  std::string query_text(std::string_view sql);

  // Milliseconds a statement waits for another connection's lock before failing with SQLITE_BUSY.
  void set_busy_timeout(int milliseconds);

  sqlite3* handle() const { return db_; }
  const std::string& path() const { return path_; }
  bool in_transaction() const;
  std::int64_t changes() const;      // rows changed by the last INSERT/UPDATE/DELETE
  bool last_error_was_busy() const;  // the last failed call met another connection's lock
  // Reads the file's header through SQLite: false if the file is not an SQLite database
  // (SQLITE_NOTADB); an empty file is a new database (true). Other failures throw core::Error.
  // This is how a store's header is checked: a raw open() and close() of the file would drop every
  // POSIX lock this process holds on it through its SQLite connections (see docs/store.md).
  bool holds_database();
  std::int64_t last_insert_rowid() const;

 private:
  Database(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
  sqlite3* db_ = nullptr;
  std::string path_;  // as given by the caller, for messages
};

// A prepared statement, reused across executions: bind, step until done, reset.
// Parameter and column indexes follow SQLite: parameters from 1, columns from 0.
class Statement {
 public:
  Statement(const Database& db, std::string_view sql);
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement();

  void bind(int index, std::int64_t value);
  void bind(int index, std::string_view text);  // copied by SQLite
  void bind_null(int index);
  // Named apart from bind(): an int argument would otherwise be ambiguous between int64 and double.
  void bind_double(int index, double value);
  void bind_blob(int index, std::span<const std::uint8_t> bytes);  // copied by SQLite

  // Executes one step: true when a row is available, false when the statement is done.
  bool step();
  // Ready for the next execution; bindings are kept (rebind them all before stepping again).
  void reset();

  std::int64_t column_int64(int column) const;
  // Valid until the next step() or reset().
  std::string_view column_text(int column) const;
  bool column_is_null(int column) const;
  double column_double(int column) const;
  // Valid until the next step() or reset(); empty for NULL or a zero-length blob.
  std::span<const std::uint8_t> column_blob(int column) const;

 private:
  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
};

// BEGIN IMMEDIATE on construction (takes the write lock at once, so two writers never deadlock
// upgrading from a read); ROLLBACK in the destructor unless commit() succeeded. Inside a transaction
// already open (store::WholeWrite) it is a savepoint of it: released by commit(), else rolled back to.
class Transaction {
 public:
  explicit Transaction(Database& db);
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction();

  void commit();

 private:
  Database& db_;
  bool nested_ = false;
  bool done_ = false;
};

}  // namespace m2mlat::store::sqlite
