// A session cut by a crash (kill -9, power loss) stays open in the store; the next recorder of
// that node closes it at the last time it holds and records the cut as a "restart" loss.
// And a store that cannot be created completely (a full disk) leaves nothing at its name.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

TEST(SessionCut, OpenSessionsOfTheNodeAreClosedAtTheirLastEventWithARestartLoss) {
  TempDir dir;
  auto store = Store::open(dir.file("s.db"));
  const auto ended = store.begin_session(make_session("vehicle", "ended"));
  store.end_session(ended, rt(1'700'000'000'000'000'500));
  const auto cut = store.begin_session(make_session("vehicle", "cut"));
  store.append_events(cut, std::vector{make_event("vehicle", "wheel", 1'700'000'000'000'001'000),
                                       make_event("vehicle", "wheel", 1'700'000'000'000'002'000)});
  const auto empty_cut = store.begin_session(make_session("vehicle", "cut-before-any-event"));
  const auto other = store.begin_session(make_session("operator", "other node"));

  const auto now = rt(1'700'000'000'999'000'000);
  const auto closed = store.close_cut_sessions("vehicle", now);
  ASSERT_EQ(closed.size(), 2u);
  EXPECT_EQ(closed[0].id, cut);
  EXPECT_EQ(closed[0].end, rt(1'700'000'000'000'002'000));  // its last committed event
  EXPECT_EQ(closed[1].id, empty_cut);
  EXPECT_EQ(closed[1].end, closed[1].start);  // nothing committed: the best bound is its start
  EXPECT_EQ(store.session(ended)->end, rt(1'700'000'000'000'000'500));  // untouched
  EXPECT_FALSE(store.session(other)->end.has_value());                  // another node's: untouched

  const auto losses = store.losses(cut);
  ASSERT_EQ(losses.size(), 1u);
  EXPECT_EQ(losses[0].kind, "restart");
  EXPECT_EQ(losses[0].channel, "");
  EXPECT_EQ(losses[0].detected_at, now);
  EXPECT_EQ(losses[0].first_missing, 3u);  // after the session's last committed seq (2)
  EXPECT_EQ(losses[0].count, 1u);
  EXPECT_EQ(store.losses(empty_cut).size(), 1u);
  // Once closed, nothing more to do.
  EXPECT_TRUE(store.close_cut_sessions("vehicle", now).empty());
  EXPECT_TRUE(store.integrity_ok());
}

TEST(StoreCreation, AFailedCreationLeavesNothingAtTheName) {
  TempDir dir;
  const auto path = dir.file("full.db");
  // A child whose files may not grow beyond 8 KiB, as on a full disk (a store needs more).
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);  // a write beyond the limit fails with EFBIG instead of killing
    rlimit limit{8192, 8192};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int status = 1;
    try {
      Store::open(path);
    } catch (const core::Error& e) {
      const std::string message = e.what();
      status =
          e.kind() == core::ErrorKind::io && message.find(path + ": cannot create the store") == 0 ? 0 : 2;
      if (status != 0) std::fprintf(stderr, "unexpected: %s\n", e.what());
    }
    std::_Exit(status);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::is_empty(std::filesystem::path(dir.file(""))))
      << "temporary files left behind";
  // With room, the same call makes a complete store, with the mode SQLite would give it.
  const mode_t before = ::umask(022);
  auto store = Store::open(path);
  ::umask(before);
  EXPECT_EQ(store.journal_mode(), "wal");
  EXPECT_TRUE(store.integrity_ok());
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);
}
