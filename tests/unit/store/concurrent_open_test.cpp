// Two processes creating the same new store at once (two recorders started together into one file):
// both must open it, each with its own session; neither may fail with "database is locked" while the
// other switches the new file to WAL. Separate processes, as in the field, so that SQLite's locks are
// the file locks between them.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <string>

#include "m2mlat/store/store.hpp"
#include "store_test_util.hpp"

using namespace m2mlat;
using namespace m2mlat::store;
using namespace m2mlat::store::test;

namespace {

// The child: opens (creating) the store, begins a session; exit status 0 on success.
[[noreturn]] void open_and_begin(const std::string& path, int barrier_fd, const char* node) {
  char go = 0;
  const bool released = ::read(barrier_fd, &go, 1) == 1;
  int status = 1;
  try {
    auto store = Store::open(path, {});
    store.begin_session(make_session(node));
    status = released ? 0 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", node, e.what());
    status = 1;
  }
  std::_Exit(status);
}

}  // namespace

TEST(ConcurrentOpen, TwoProcessesCreatingOneNewStoreBothSucceed) {
  TempDir dir;
  for (int round = 0; round < 20; ++round) {
    const auto path = dir.file("shared-" + std::to_string(round) + ".db");
    int barrier[2];
    ASSERT_EQ(::pipe(barrier), 0);
    pid_t children[2];
    const char* nodes[2] = {"operator", "vehicle"};
    for (int i = 0; i < 2; ++i) {
      children[i] = ::fork();
      ASSERT_GE(children[i], 0);
      if (children[i] == 0) open_and_begin(path, barrier[0], nodes[i]);
    }
    // Release both at once: two bytes, one each.
    ASSERT_EQ(::write(barrier[1], "gg", 2), 2);
    ::close(barrier[0]);
    ::close(barrier[1]);
    for (pid_t child : children) {
      int status = 0;
      ASSERT_EQ(::waitpid(child, &status, 0), child);
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "round " << round;
    }
    auto store = Store::open(path, {});
    EXPECT_EQ(store.sessions().size(), 2u) << "round " << round;
    EXPECT_EQ(store.journal_mode(), "wal");
  }
}
