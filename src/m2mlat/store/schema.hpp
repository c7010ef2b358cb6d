// The store's SQLite schema and its forward migrations.
//
// The schema version is PRAGMA user_version = the number of migration steps applied. A store file
// is recognised by PRAGMA application_id and by the meta table's format name; a newer version than
// this code knows, a foreign SQLite file or a non-SQLite file is refused with a message naming the
// file. Each step runs in its own transaction, so a crash during a migration leaves the previous
// version intact.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>

#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::schema {

// "M2ML" in the SQLite file header (offset 68), so that file(1)-like tools can tell the format.
inline constexpr std::int32_t kApplicationId = 0x4D324D4C;
// The meta table's row 'format'.
inline constexpr std::string_view kFormatName = "m2mlat-store";

struct Migration {
  std::string_view description;  // what the step changes, for messages
  std::string_view sql;          // DDL/DML run inside the step's transaction
};

// The ordered steps of this code; after step i (1-based), user_version = i. Append only: a released
// step is never edited, since stores in the field were created by it.
std::span<const Migration> migrations();
int latest_version();

// Checks that `db` is an empty database or an m2mlat store that `steps` can read. Returns its
// version (0 = empty). Throws core::Error(data) naming the file otherwise.
int identify(sqlite::Database& db, std::span<const Migration> steps);

// Table name -> the names of its columns.
using Tables = std::map<std::string, std::set<std::string>>;

// The tables and columns of the main database of `db` (SQLite's own tables left out).
Tables tables_of(sqlite::Database& db);

// The tables and columns that `steps` create, run on an empty in-memory database.
Tables tables_created_by(std::span<const Migration> steps);

// The tables and columns a store of `version` has: for the latest version a list kept beside the
// steps (equal to tables_created_by(migrations()), which the unit tests check); for an older one,
// the first `version` steps run in memory (once per upgrade, so their cost does not matter).
Tables expected_tables(int version);

// Checks that `db`, identified as a store of `version`, has every table and column of
// expected_tables(version), so a damaged or foreign schema is a data error naming the file and what
// is missing, not a failure of the first statement that needs it. Throws core::Error(data).
void check_tables(sqlite::Database& db, int version);

// Applies the steps from the store's version up to steps.size(), one transaction each; creating a
// store (version 0 -> 1) also writes the application id and the meta rows. Safe against a second
// process migrating at the same time. Returns the version reached.
int migrate(sqlite::Database& db, std::span<const Migration> steps);

}  // namespace m2mlat::store::schema
