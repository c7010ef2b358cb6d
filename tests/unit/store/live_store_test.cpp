// A store another process opens and closes while this process holds it: SQLite's POSIX locks are
// what tells the other process's last close that the -wal is still in use. Closing any descriptor of
// the file in this process drops them all, so no part of the store may open the file itself (the
// header was once checked with std::ifstream: a second Store::open in the agent let `sqlite3 STORE`
// delete the -wal under the agent's writer, and committed, served events were lost). Here the
// writer keeps committing while, in this process, further Stores are opened and closed and files
// are sniffed, and a spawned sqlite3 opens and closes the store each round: the -wal must stay and
// every committed event must be readable at the end.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

extern char** environ;

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

// Runs `sqlite3 PATH SQL` as another process; returns its exit status and first output line, or
// nullopt if the sqlite3 program is missing.
std::optional<std::pair<int, std::string>> run_sqlite3(const std::string& path, const std::string& sql,
                                                       const std::string& out_file) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::vector<std::string> args{"sqlite3", path, sql};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "sqlite3", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return std::nullopt;
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return std::pair{-1, std::string()};
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return std::nullopt;  // not installed
  std::string line;
  if (std::FILE* f = std::fopen(out_file.c_str(), "r")) {
    char buffer[256] = {};
    if (std::fgets(buffer, sizeof buffer, f) != nullptr) line = buffer;
    std::fclose(f);
  }
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, line};
}

std::vector<core::Event> events(std::int64_t first, int n) {
  std::vector<core::Event> out;
  for (int i = 0; i < n; ++i) out.push_back(make_event("vehicle", "wheel", (first + i) * 1'000'000));
  return out;
}

}  // namespace

TEST(LiveStore, OpeningAndClosingElsewhereNeverRemovesTheWalOfALiveWriter) {
  TempDir dir;
  const auto path = dir.file("live.db");
  const auto wal = path + "-wal";
  auto writer = Store::open(path);
  const auto session = writer.begin_session(make_session("vehicle"));
  std::int64_t committed = 0;
  writer.append_events(session, events(committed, 50));
  committed += 50;
  ASSERT_TRUE(std::filesystem::exists(wal));

  for (int round = 0; round < 25; ++round) {
    // In this process: a reader, a second writer and the sniffing the commands do.
    {
      Options read_only;
      read_only.read_only = true;
      auto reader = Store::open(path, read_only);
      EXPECT_EQ(reader.event_count(), committed) << "round " << round;
    }
    { auto second = Store::open(path); }
    EXPECT_TRUE(is_sqlite_database(path));
    // Another process opens and closes the store: had this process lost its locks, that close
    // would checkpoint and delete the -wal.
    const auto other = run_sqlite3(path, "select count(*) from events", dir.file("out.txt"));
    if (!other) GTEST_SKIP() << "the sqlite3 program is not installed";
    EXPECT_EQ(other->first, 0) << "round " << round;
    EXPECT_EQ(other->second, std::to_string(committed)) << "round " << round;
    ASSERT_TRUE(std::filesystem::exists(wal))
        << "round " << round << ": the -wal was removed under the writer";
    writer.append_events(session, events(committed, 10));
    committed += 10;
  }
  // Every commit of the writer went to the log every reader sees.
  Options read_only;
  read_only.read_only = true;
  auto reader = Store::open(path, read_only);
  EXPECT_EQ(reader.event_count(), committed);
  EXPECT_EQ(reader.last_seq(), committed);
  EXPECT_TRUE(writer.integrity_ok());
}

TEST(LiveStore, IsSqliteDatabaseTellsStoresFromOtherFiles) {
  TempDir dir;
  { auto store = Store::open(dir.file("a.db")); }
  EXPECT_TRUE(is_sqlite_database(dir.file("a.db")));
  {
    std::FILE* f = std::fopen(dir.file("b.csv").c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("remote_station_ns,vehicle_ns\n1,2\n", f);
    std::fclose(f);
  }
  EXPECT_FALSE(is_sqlite_database(dir.file("b.csv")));
  std::fclose(std::fopen(dir.file("empty").c_str(), "w"));
  EXPECT_FALSE(is_sqlite_database(dir.file("empty")));
  EXPECT_FALSE(is_sqlite_database(dir.file("missing")));
  EXPECT_FALSE(is_sqlite_database(dir.file("")));  // the directory itself
  ASSERT_EQ(::mkfifo(dir.file("fifo").c_str(), 0600), 0);
  EXPECT_FALSE(is_sqlite_database(dir.file("fifo")));  // and returns: nothing opened it
}
