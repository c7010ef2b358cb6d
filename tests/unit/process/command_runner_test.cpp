// ProcessRunner with real processes: output, status, a timeout, and a program that does not exist.
#include "m2mlat/process/command_runner.hpp"

#include <gtest/gtest.h>
#include <time.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::process {
namespace {

TEST(ProcessRunner, CollectsOutputAndExitStatus) {
  ProcessRunner r;
  const auto res = r.run({"/bin/sh", "-c", "echo out; echo err >&2; exit 3"}, std::chrono::seconds(10));
  EXPECT_TRUE(res.started);
  EXPECT_FALSE(res.timed_out);
  EXPECT_EQ(res.exit_code, 3);
  EXPECT_EQ(res.out, "out\n");
  EXPECT_EQ(res.err, "err\n");
  EXPECT_FALSE(res.ok());
  EXPECT_TRUE(r.run({"true"}, std::chrono::seconds(10)).ok());
}

TEST(ProcessRunner, LargeOutputIsReadWhole) {
  ProcessRunner r;
  const auto res = r.run({"/bin/sh", "-c", "head -c 300000 /dev/zero"}, std::chrono::seconds(10));
  EXPECT_TRUE(res.ok());
  EXPECT_EQ(res.out.size(), 300000u);
}

TEST(ProcessRunner, KillsAfterTheTimeout) {
  ProcessRunner r;
  timespec t0{}, t1{};
  clock_gettime(CLOCK_MONOTONIC, &t0);
  const auto res = r.run({"sleep", "10"}, std::chrono::milliseconds(200));
  clock_gettime(CLOCK_MONOTONIC, &t1);
  EXPECT_TRUE(res.timed_out);
  EXPECT_FALSE(res.ok());
  EXPECT_LT(t1.tv_sec - t0.tv_sec, 5);
}

TEST(ProcessRunner, AMissingProgramIsNotStarted) {
  ProcessRunner r;
  const auto res = r.run({"/nonexistent/m2mlat-no-such-program"}, std::chrono::seconds(1));
  EXPECT_FALSE(res.started);
  EXPECT_NE(res.err.find("No such file"), std::string::npos) << res.err;
}

TEST(CommandLine, QuotesArgumentsWithSpaces) {
  EXPECT_EQ(command_line({"pmc", "-u", "GET TIME_STATUS_NP"}), "pmc -u 'GET TIME_STATUS_NP'");
}

// One failure format for every program: the command line, then why (status and what it said, its
// standard error before its standard output, escaped for the terminal).
TEST(CommandError, NamesTheCommandTheStatusAndWhatItSaid) {
  ProcessRunner r;
  const std::vector<std::string> argv{"/bin/sh", "-c",
                                      "echo quiet; printf 'bad\\033[1m news\\n' >&2; exit 4"};
  const auto res = r.run(argv, std::chrono::seconds(10));
  EXPECT_EQ(failure_text(res), "exit status 4: bad\\x1b[1m news");
  const core::Error e = command_error(argv, res);
  EXPECT_EQ(e.kind(), core::ErrorKind::io);
  EXPECT_EQ(std::string(e.what()), command_line(argv) + ": exit status 4: bad\\x1b[1m news");

  const auto only_out =
      r.run({"/bin/sh", "-c", "echo 506 Cannot talk to daemon; exit 1"}, std::chrono::seconds(10));
  EXPECT_EQ(failure_text(only_out), "exit status 1: 506 Cannot talk to daemon");
  EXPECT_EQ(failure_text(r.run({"false"}, std::chrono::seconds(10))), "exit status 1");
  EXPECT_EQ(failure_text(r.run({"sleep", "10"}, std::chrono::milliseconds(100))), "timed out");
  EXPECT_EQ(failure_text(r.run({"/nonexistent/m2mlat-x"}, std::chrono::seconds(1))),
            "/nonexistent/m2mlat-x: No such file or directory");
  EXPECT_EQ(failure_text(r.run({"true"}, std::chrono::seconds(10))), "");
}

}  // namespace
}  // namespace m2mlat::process
