// The archive's libpq connection: connection strings, statements, COPY, transactions.
#include "m2mlat/archive/connection.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>

#include "m2mlat/archive/libpq.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::archive {

namespace {

// libpq's functions, loaded on first use (libpq.hpp).
const libpq::Api& pq() { return libpq::api(); }

std::string trimmed_message(const char* text) {
  std::string s = text == nullptr ? "" : text;
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

struct ResultDeleter {
  void operator()(PGresult* r) const { pq().PQclear(r); }
};
using Result = std::unique_ptr<PGresult, ResultDeleter>;

// The password a connection string holds, found by its text alone (so also in one libpq cannot
// parse): a URL's "user:password@", or a "password=" keyword or query parameter. Empty if none.
std::string password_in(const std::string& conninfo) {
  if (const auto scheme = conninfo.find("://"); scheme != std::string::npos) {
    const auto authority =
        conninfo.substr(scheme + 3, conninfo.find_first_of("/?", scheme + 3) - (scheme + 3));
    const auto at = authority.rfind('@');
    if (at != std::string::npos && authority.find(':') < at)
      return authority.substr(authority.find(':') + 1, at - authority.find(':') - 1);
  }
  if (const auto key = conninfo.find("password="); key != std::string::npos) {
    const auto start = key + 9;
    return conninfo.substr(start, conninfo.find_first_of("& \t", start) - start);
  }
  return {};
}

// A message of libpq about `conninfo` (which it may quote) with the password replaced by "***".
std::string scrubbed(std::string message, const std::string& conninfo) {
  const auto password = password_in(conninfo);
  if (password.empty()) return message;
  for (auto at = message.find(password); at != std::string::npos; at = message.find(password, at + 3))
    message.replace(at, password.size(), "***");
  return message;
}

}  // namespace

bool is_archive_url(const std::string& text) {
  return text.starts_with("postgresql://") || text.starts_with("postgres://");
}

std::string resolve_conninfo(const std::string& url, const std::string& url_file) {
  if (!url.empty() && !url_file.empty())
    throw core::Error(core::ErrorKind::usage, "give the archive's connection string or --url-file, not both");
  std::string conninfo = url;
  if (!url_file.empty()) {
    std::ifstream in(url_file);
    if (!in)
      throw core::Error(core::ErrorKind::no_input,
                        fmt::format("{}: cannot read the connection string", url_file));
    std::getline(in, conninfo);
    while (!conninfo.empty() && (conninfo.back() == '\r' || conninfo.back() == ' ')) conninfo.pop_back();
    if (conninfo.empty())
      throw core::Error(core::ErrorKind::usage, fmt::format("{}: line 1: no connection string", url_file));
  }
  describe(conninfo);  // refuses what libpq cannot parse, before anything connects
  return conninfo;
}

std::string describe(const std::string& conninfo) {
  char* error = nullptr;
  PQconninfoOption* options = pq().PQconninfoParse(conninfo.c_str(), &error);
  if (options == nullptr) {
    // libpq's message may quote the whole string: never its password.
    const auto what = scrubbed(trimmed_message(error), conninfo);
    pq().PQfreemem(error);
    throw core::Error(core::ErrorKind::usage, fmt::format("archive connection string: {}", what));
  }
  std::string user, host, port, dbname;
  for (auto* o = options; o->keyword != nullptr; ++o) {
    const std::string key = o->keyword;
    const char* value = o->val;
    if (value == nullptr) continue;
    if (key == "user") user = value;
    if (key == "host" || (key == "hostaddr" && host.empty())) host = value;
    if (key == "port") port = value;
    if (key == "dbname") dbname = value;
  }
  pq().PQconninfoFree(options);
  // Unset parts are libpq's defaults (PG* variables, the local socket, the login name).
  const auto or_env = [](std::string value, const char* variable, const char* fallback) {
    if (!value.empty()) return value;
    const char* env = std::getenv(variable);
    return std::string(env != nullptr && *env != '\0' ? env : fallback);
  };
  user = or_env(user, "PGUSER", "(login name)");
  host = or_env(host, "PGHOST", "local socket");
  port = or_env(port, "PGPORT", "5432");
  dbname = or_env(dbname, "PGDATABASE", user.c_str());
  return fmt::format("{}@{}:{}/{}", user, host, port, dbname);
}

const std::string& Rows::at(std::size_t r, std::size_t c) const {
  const auto& v = rows.at(r).at(c);
  if (!v)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("archive: column {} of row {} is NULL", columns.at(c), r));
  return *v;
}

struct Connection::Impl {
  PGconn* conn = nullptr;
  std::string name;
  ~Impl() {
    if (conn != nullptr) pq().PQfinish(conn);
  }
  [[noreturn]] void fail(const std::string& what, const char* message) const {
    throw core::Error(core::ErrorKind::io,
                      fmt::format("archive {}: {}: {}", name, what, trimmed_message(message)));
  }
};

Connection::Connection(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Connection::Connection(Connection&&) noexcept = default;
Connection& Connection::operator=(Connection&&) noexcept = default;
Connection::~Connection() = default;

Connection Connection::open(const std::string& conninfo) {
  auto impl = std::make_unique<Impl>();
  impl->name = describe(conninfo);
  impl->conn = pq().PQconnectdb(conninfo.c_str());
  if (impl->conn == nullptr)
    throw core::Error(core::ErrorKind::io, fmt::format("archive {}: out of memory", impl->name));
  if (pq().PQstatus(impl->conn) != CONNECTION_OK)
    impl->fail("cannot connect",
               scrubbed(trimmed_message(pq().PQerrorMessage(impl->conn)), conninfo).c_str());
  // Notices (e.g. "relation already exists, skipping") are not the user's business.
  pq().PQsetNoticeProcessor(
      impl->conn, [](void*, const char*) {}, nullptr);
  return Connection(std::move(impl));
}

const std::string& Connection::name() const { return impl_->name; }

Rows Connection::exec(const std::string& sql, const std::vector<std::optional<std::string>>& params) {
  std::vector<const char*> values;
  values.reserve(params.size());
  for (const auto& p : params) values.push_back(p ? p->c_str() : nullptr);
  // Without parameters a text may hold several statements (a migration): PQexec takes those.
  Result result(params.empty() ? pq().PQexec(impl_->conn, sql.c_str())
                               : pq().PQexecParams(impl_->conn, sql.c_str(), static_cast<int>(values.size()),
                                                   nullptr, values.data(), nullptr, nullptr, 0));
  const auto status = pq().PQresultStatus(result.get());
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
    // The statement's first words say which one failed.
    const auto start = sql.find_first_not_of(" \n");
    const auto text = start == std::string::npos ? std::string() : sql.substr(start, 48);
    impl_->fail(text.substr(0, text.find('\n')), pq().PQresultErrorMessage(result.get()));
  }
  Rows rows;
  const int n_fields = pq().PQnfields(result.get());
  for (int c = 0; c < n_fields; ++c) rows.columns.emplace_back(pq().PQfname(result.get(), c));
  for (int r = 0; r < pq().PQntuples(result.get()); ++r) {
    auto& row = rows.rows.emplace_back();
    for (int c = 0; c < n_fields; ++c)
      if (pq().PQgetisnull(result.get(), r, c) != 0)
        row.emplace_back(std::nullopt);
      else
        row.emplace_back(std::string(pq().PQgetvalue(result.get(), r, c),
                                     static_cast<std::size_t>(pq().PQgetlength(result.get(), r, c))));
  }
  return rows;
}

std::int64_t Connection::copy_in(const std::string& copy_sql, const std::string& data) {
  Result start(pq().PQexec(impl_->conn, copy_sql.c_str()));
  if (pq().PQresultStatus(start.get()) != PGRES_COPY_IN)
    impl_->fail(copy_sql, pq().PQresultErrorMessage(start.get()));
  if (pq().PQputCopyData(impl_->conn, data.data(), static_cast<int>(data.size())) != 1 ||
      pq().PQputCopyEnd(impl_->conn, nullptr) != 1)
    impl_->fail(copy_sql, pq().PQerrorMessage(impl_->conn));
  Result end(pq().PQgetResult(impl_->conn));
  if (pq().PQresultStatus(end.get()) != PGRES_COMMAND_OK)
    impl_->fail(copy_sql, pq().PQresultErrorMessage(end.get()));
  const char* tuples = pq().PQcmdTuples(end.get());
  // Drain: libpq returns NULL once the command is complete.
  while (Result more{pq().PQgetResult(impl_->conn)}) {
  }
  return tuples != nullptr && *tuples != '\0' ? std::stoll(tuples) : 0;
}

Transaction::Transaction(Connection& connection) : connection_(connection) { connection_.exec("BEGIN"); }

Transaction::~Transaction() {
  if (done_) return;
  try {
    connection_.exec("ROLLBACK");
  } catch (...) {  // the connection is gone: the server rolls back on its own
  }
}

void Transaction::commit() {
  connection_.exec("COMMIT");
  done_ = true;
}

std::string copy_text(const std::string& field) {
  std::string out;
  out.reserve(field.size());
  for (const char ch : field) {
    switch (ch) {
      case '\\': out += "\\\\"; break;
      case '\t': out += "\\t"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      default: out += ch;
    }
  }
  return out;
}

}  // namespace m2mlat::archive
