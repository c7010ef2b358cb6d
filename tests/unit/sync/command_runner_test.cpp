// ProcessRunner with real processes: output, status, a timeout, and a program that does not exist.
#include "m2mlat/sync/command_runner.hpp"

#include <gtest/gtest.h>
#include <time.h>

namespace m2mlat::sync {
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

}  // namespace
}  // namespace m2mlat::sync
