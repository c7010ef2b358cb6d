// Schema versions and migrations, and how foreign or future files are refused.
#include "m2mlat/store/schema.hpp"

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

std::string open_error(const std::string& path, const Options& options = {}) {
  try {
    Store::open(path, options);
  } catch (const core::Error& e) {
    return e.what();
  }
  return "no error";
}

core::ErrorKind open_error_kind(const std::string& path, const Options& options = {}) {
  try {
    Store::open(path, options);
  } catch (const core::Error& e) {
    return e.kind();
  }
  return core::ErrorKind::internal;
}


void write_file(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
}

}  // namespace

TEST(StoreSchema, NewStoreHasTheLatestVersionAndIdentifiesItself) {
  TempDir dir;
  const auto path = dir.file("new.m2mlat");
  {
    auto store = Store::open(path);
    EXPECT_EQ(store.schema_version(), schema::latest_version());
    EXPECT_GE(schema::latest_version(), 1);
    EXPECT_EQ(store.journal_mode(), "wal");
    EXPECT_TRUE(contains(store.created_by(), "m2mlat "));
    EXPECT_TRUE(store.integrity_ok());
    EXPECT_EQ(store.last_seq(), 0);
  }
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  EXPECT_EQ(db.query_int("PRAGMA user_version"), schema::latest_version());
  EXPECT_EQ(db.query_int("PRAGMA application_id"), schema::kApplicationId);
  EXPECT_EQ(db.query_text("SELECT value FROM meta WHERE key = 'format'"), schema::kFormatName);
}

TEST(StoreSchema, AnEmptyFileBecomesAStore) {
  TempDir dir;
  const auto path = dir.file("empty.m2mlat");
  write_file(path, "");
  auto store = Store::open(path);
  EXPECT_EQ(store.schema_version(), schema::latest_version());
  EXPECT_EQ(store.begin_session(make_session("op")), 1);
}

TEST(StoreSchema, MissingFileWithoutCreateOrReadOnly) {
  TempDir dir;
  const auto path = dir.file("absent.m2mlat");
  EXPECT_EQ(open_error_kind(path, Options{.create = false}), core::ErrorKind::no_input);
  EXPECT_EQ(open_error_kind(path, Options{.read_only = true}), core::ErrorKind::no_input);
  EXPECT_TRUE(contains(open_error(path, Options{.read_only = true}), path));
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(StoreSchema, AFutureVersionIsRefusedNamingFileAndVersions) {
  TempDir dir;
  const auto path = dir.file("future.m2mlat");
  { Store::open(path).begin_session(make_session("op")); }
  const int future = schema::latest_version() + 5;
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    db.exec("PRAGMA user_version = " + std::to_string(future));
  }
  const auto message = open_error(path);
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "version " + std::to_string(future))) << message;
  EXPECT_TRUE(contains(message, std::to_string(schema::latest_version()))) << message;
  EXPECT_EQ(open_error_kind(path), core::ErrorKind::data);
  EXPECT_EQ(open_error_kind(path, Options{.read_only = true}), core::ErrorKind::data);
  // Refusing did not touch it.
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  EXPECT_EQ(db.query_int("PRAGMA user_version"), future);
}

TEST(StoreSchema, ANonSqliteFileIsRefusedUnchanged) {
  TempDir dir;
  const auto path = dir.file("notes.txt");
  const std::string text = "vehicle_ns,operator_ns\n1,2\n";
  write_file(path, text);
  const auto message = open_error(path);
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "not an m2mlat store")) << message;
  EXPECT_EQ(open_error_kind(path), core::ErrorKind::data);
  std::ifstream in(path, std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), text);
  // Short garbage too.
  write_file(path, "SQLite");
  EXPECT_TRUE(contains(open_error(path), "not an SQLite database"));
  EXPECT_TRUE(contains(open_error(dir.file("")), "not an m2mlat store"));  // a directory
}

TEST(StoreSchema, AnotherApplicationsSqliteFileIsRefused) {
  TempDir dir;
  const auto path = dir.file("other.db");
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
    db.exec("CREATE TABLE photos (id INTEGER PRIMARY KEY, name TEXT)");
  }
  const auto message = open_error(path);
  EXPECT_TRUE(contains(message, path)) << message;
  EXPECT_TRUE(contains(message, "not an m2mlat store")) << message;
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  EXPECT_EQ(db.query_int("SELECT count(*) FROM sqlite_schema"), 1);
  EXPECT_EQ(db.query_int("PRAGMA user_version"), 0);
}

TEST(StoreSchema, WrongFormatNameIsRefused) {
  TempDir dir;
  const auto path = dir.file("renamed.m2mlat");
  { Store::open(path); }
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
    db.exec("UPDATE meta SET value = 'something-else' WHERE key = 'format'");
  }
  EXPECT_TRUE(contains(open_error(path), "something-else"));
}

// The runner brings an older store forward step by step, keeping its data, and a failing step
// leaves the store at its previous version.
TEST(StoreSchema, MigrationsRunForwardAndAFailedStepChangesNothing) {
  TempDir dir;
  const auto path = dir.file("old.m2mlat");
  { Store::open(path).begin_session(make_session("op", "kept")); }
  const auto current = schema::migrations();
  std::vector<schema::Migration> steps(current.begin(), current.end());

  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
  steps.push_back({"a broken step", "CREATE TABLE extra (x INTEGER); INSERT INTO no_such_table VALUES (1);"});
  try {
    schema::migrate(db, steps);
    ADD_FAILURE() << "the broken step ran";
  } catch (const core::Error& e) {
    EXPECT_TRUE(contains(e.what(), "a broken step")) << e.what();
    EXPECT_TRUE(contains(e.what(), "version " + std::to_string(current.size() + 1))) << e.what();
  }
  EXPECT_EQ(db.query_int("PRAGMA user_version"), static_cast<std::int64_t>(current.size()));
  EXPECT_EQ(db.query_int("SELECT count(*) FROM sqlite_schema WHERE name = 'extra'"), 0);

  steps.back() = {"add notes", "CREATE TABLE notes (session_id INTEGER REFERENCES sessions (id), text TEXT)"};
  steps.push_back({"fill notes", "INSERT INTO notes SELECT id, label FROM sessions"});
  EXPECT_EQ(schema::identify(db, steps), static_cast<int>(current.size()));
  EXPECT_EQ(schema::migrate(db, steps), static_cast<int>(steps.size()));
  EXPECT_EQ(db.query_int("PRAGMA user_version"), static_cast<std::int64_t>(steps.size()));
  EXPECT_EQ(db.query_text("SELECT text FROM notes"), "kept");
  EXPECT_EQ(schema::migrate(db, steps), static_cast<int>(steps.size()));  // nothing left to do
  // This build's code does not know those steps: the store is now from the future.
  EXPECT_THROW(schema::identify(db, current), core::Error);
}

// An open compares the store's tables with a list kept in schema.cpp, not with the steps run in
// memory: the list must be exactly what the steps create, and what a new store has.
TEST(StoreSchema, TheLatestVersionsTableListIsWhatTheStepsCreate) {
  const auto listed = schema::expected_tables(schema::latest_version());
  EXPECT_EQ(listed, schema::tables_created_by(schema::migrations()));
  EXPECT_EQ(listed.size(), 10U);
  EXPECT_EQ(listed.at("origins").size(), 6U);

  TempDir dir;
  const auto path = dir.file("new.m2mlat");
  { Store::open(path); }
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  EXPECT_EQ(schema::tables_of(db), listed);
}

// An older store is checked against its own version's tables (before its upgrade).
TEST(StoreSchema, AnOlderVersionsTablesAreThoseOfItsSteps) {
  const auto version3 = schema::expected_tables(3);
  EXPECT_EQ(version3, schema::tables_created_by(schema::migrations().first(3)));
  EXPECT_TRUE(version3.contains("rate_blocks"));
  EXPECT_FALSE(version3.contains("markers"));
  EXPECT_FALSE(version3.at("origins").contains("marker_id"));
}

TEST(StoreSchema, ReadOnlyOpenOfAnEmptyDatabaseDoesNotMakeAStore) {
  TempDir dir;
  const auto path = dir.file("v0.m2mlat");
  {
    auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
    db.exec("VACUUM");
  }
  // An empty database opened read-only is not a store, and is not turned into one.
  EXPECT_TRUE(contains(open_error(path, Options{.read_only = true}), "not an m2mlat store"));
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_only);
  EXPECT_EQ(db.query_int("SELECT count(*) FROM sqlite_schema"), 0);
}

TEST(StoreSchema, SqliteErrorsNameTheFile) {
  TempDir dir;
  const auto path = dir.file("errors.m2mlat");
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write_create);
  try {
    db.exec("SELEKT 1");
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_TRUE(contains(e.what(), "errors.m2mlat")) << e.what();
    EXPECT_TRUE(contains(e.what(), "syntax error")) << e.what();
    EXPECT_EQ(e.kind(), core::ErrorKind::internal);
  }
  db.exec("CREATE TABLE t (x INTEGER NOT NULL UNIQUE)");
  sqlite::Statement insert(db, "INSERT INTO t (x) VALUES (?1)");
  insert.bind(1, std::int64_t{1});
  insert.step();
  insert.reset();
  try {
    insert.step();  // the same value again
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_TRUE(contains(e.what(), "UNIQUE")) << e.what();
  }
  {
    sqlite::Transaction transaction(db);
    db.exec("INSERT INTO t (x) VALUES (2)");
  }  // not committed: rolled back
  EXPECT_EQ(db.query_int("SELECT count(*) FROM t"), 1);
  {
    sqlite::Transaction transaction(db);
    db.exec("INSERT INTO t (x) VALUES (3)");
    transaction.commit();
  }
  EXPECT_EQ(db.query_int("SELECT count(*) FROM t"), 2);
}
