// A connection to the lab's archive (PostgreSQL, through Debian's libpq): where the connection
// string comes from, how it is shown (never with its password), and the few calls the archive
// makes (statements with text parameters, COPY in, transactions). Every failure is a core::Error
// naming the database and what PostgreSQL said: io when the server cannot be reached or refuses a
// statement, usage for a malformed connection string.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace m2mlat::archive {

// True for a text the archive takes as a connection string: "postgresql://..." or "postgres://...".
bool is_archive_url(const std::string& text);

// The connection string to use: `url` if given, else the first line of `url_file` (so that a
// password need not be on a command line), else "" (libpq then takes PGHOST, PGPORT, PGDATABASE,
// PGUSER, PGPASSWORD and PGPASSFILE from the environment). Throws core::Error: usage if both are
// given or the text is not a connection string libpq parses; no_input if the file cannot be read.
std::string resolve_conninfo(const std::string& url, const std::string& url_file);

// What a message shows of a connection string: "user@host:port/dbname" from the parsed options
// (the environment's defaults filled in by libpq), never the password. Throws core::Error(usage)
// if libpq cannot parse it.
std::string describe(const std::string& conninfo);

// The rows of one statement's result, as text (nullopt = SQL NULL).
struct Rows {
  std::vector<std::string> columns;
  std::vector<std::vector<std::optional<std::string>>> rows;
  // The value of row r, column c; throws core::Error(data) for NULL.
  const std::string& at(std::size_t r, std::size_t c) const;
};

class Connection {
 public:
  // Connects (libpq's PQconnectdb). Throws core::Error(io) naming describe(conninfo).
  static Connection open(const std::string& conninfo);

  Connection(Connection&&) noexcept;
  Connection& operator=(Connection&&) noexcept;
  ~Connection();

  const std::string& name() const;  // describe(conninfo)

  // One statement with $1, $2, ... bound to `params` as text (nullopt = NULL).
  Rows exec(const std::string& sql, const std::vector<std::optional<std::string>>& params = {});
  // COPY ... FROM STDIN with `data` in COPY's text format (copy_text below escapes a field).
  // Returns the number of rows copied.
  std::int64_t copy_in(const std::string& copy_sql, const std::string& data);

 private:
  struct Impl;
  explicit Connection(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// A transaction: BEGIN on construction, ROLLBACK on destruction unless commit() ran.
class Transaction {
 public:
  explicit Transaction(Connection& connection);
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction();
  void commit();

 private:
  Connection& connection_;
  bool done_ = false;
};

// A field in COPY's text format: backslash, tab, newline and carriage return escaped.
std::string copy_text(const std::string& field);

}  // namespace m2mlat::archive
