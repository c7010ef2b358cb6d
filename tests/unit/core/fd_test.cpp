// core::Fd: the descriptor it holds is closed exactly once, by whoever holds it last (real pipes:
// a pipe's read end sees end-of-file only when every write end is closed).
#include "m2mlat/core/fd.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <utility>

namespace m2mlat::core {
namespace {

struct Pipe {
  Fd read, write;
  Pipe() {
    std::array<int, 2> ends{-1, -1};
    EXPECT_EQ(::pipe2(ends.data(), O_CLOEXEC | O_NONBLOCK), 0);
    read.reset(ends[0]);
    write.reset(ends[1]);
  }
};

// True if `fd` is an open descriptor of this process.
bool is_open(int fd) { return ::fcntl(fd, F_GETFD) != -1 || errno != EBADF; }

// End of file on the read end: every write end is closed.
bool at_eof(const Fd& read) {
  char c = 0;
  return ::read(read.get(), &c, 1) == 0;
}

TEST(Fd, ClosesWhenItsOwnerGoes) {
  Pipe pipe;
  const int raw = pipe.write.get();
  { const Fd owner(pipe.write.release()); }
  EXPECT_FALSE(is_open(raw));
  EXPECT_TRUE(at_eof(pipe.read));
}

TEST(Fd, EmptyByDefaultAndAfterRelease) {
  Fd none;
  EXPECT_FALSE(none);
  EXPECT_EQ(none.get(), -1);
  EXPECT_EQ(none.close(), 0);
  Fd failed(-1);  // open(2)'s failure holds nothing
  EXPECT_FALSE(failed);

  Pipe pipe;
  const int raw = pipe.write.release();
  EXPECT_FALSE(pipe.write);
  EXPECT_TRUE(is_open(raw));  // released: the caller's to close
  ::close(raw);
}

TEST(Fd, MoveHandsOverWithoutClosing) {
  Pipe pipe;
  const int raw = pipe.write.get();
  Fd moved(std::move(pipe.write));
  EXPECT_EQ(moved.get(), raw);
  EXPECT_FALSE(pipe.write);
  EXPECT_TRUE(is_open(raw));

  Pipe other;
  const int other_raw = other.write.get();
  moved = std::move(other.write);  // the descriptor held before is closed
  EXPECT_FALSE(is_open(raw));
  EXPECT_EQ(moved.get(), other_raw);
  EXPECT_TRUE(at_eof(pipe.read));
  auto& same = moved;  // through a reference: the compiler would refuse a plain self-move
  moved = std::move(same);  // self-assignment keeps it
  EXPECT_TRUE(is_open(other_raw));
}

TEST(Fd, ResetClosesTheOldAndTakesTheNew) {
  Pipe a, b;
  const int a_raw = a.write.get();
  const int b_raw = b.write.release();
  a.write.reset(b_raw);
  EXPECT_FALSE(is_open(a_raw));
  EXPECT_TRUE(at_eof(a.read));
  EXPECT_EQ(a.write.get(), b_raw);
  a.write.reset();
  EXPECT_FALSE(a.write);
  EXPECT_FALSE(is_open(b_raw));
}

TEST(Fd, CloseReportsTheResult) {
  Pipe pipe;
  const int raw = pipe.write.get();
  EXPECT_EQ(pipe.write.close(), 0);
  EXPECT_FALSE(pipe.write);
  EXPECT_FALSE(is_open(raw));
  EXPECT_EQ(pipe.write.close(), 0);  // nothing held: nothing closed twice
}

}  // namespace
}  // namespace m2mlat::core
