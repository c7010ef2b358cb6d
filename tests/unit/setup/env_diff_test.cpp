// The env file merge (setup/env_file) and the line diff (setup/diff).
#include <gtest/gtest.h>

#include "m2mlat/setup/diff.hpp"
#include "m2mlat/setup/env_file.hpp"

namespace m2mlat::setup {
namespace {

TEST(SetupEnv, NewFileGetsHeaderAndKeys) {
  const auto text = merge_env("", {{"A", "1"}, {"B", "x y"}}, "m2mlat-agent@vehicle");
  EXPECT_EQ(
      text,
      "# Environment of m2mlat-agent@vehicle (packaging/m2mlat-agent@.service), kept up to date by `m2mlat "
      "setup`.\nA=1\nB=x y\n");
}

TEST(SetupEnv, ReplacesInPlaceKeepsOthersDropsDuplicates) {
  const std::string existing = "# mine\nM2MLAT_LISTEN=0.0.0.0:1\nOTHER=keep\n  M2MLAT_LISTEN = 1.2.3.4:5\n";
  const auto text = merge_env(existing, {{"M2MLAT_LISTEN", "10.0.0.2:8470"}, {"M2MLAT_IRQ_CPU", "2"}}, "x");
  EXPECT_EQ(text, "# mine\nM2MLAT_LISTEN=10.0.0.2:8470\nOTHER=keep\nM2MLAT_IRQ_CPU=2\n");
  // Idempotent: merging the same keys again changes nothing.
  EXPECT_EQ(merge_env(text, {{"M2MLAT_LISTEN", "10.0.0.2:8470"}, {"M2MLAT_IRQ_CPU", "2"}}, "x"), text);
  EXPECT_EQ(env_value(text, "OTHER"), "keep");
  EXPECT_EQ(env_value(text, "M2MLAT_IRQ_CPU"), "2");
  EXPECT_FALSE(env_value(text, "mine").has_value());
  EXPECT_EQ(env_path("vehicle"), "/etc/m2mlat/vehicle.env");
}

TEST(SetupDiff, EqualTextsHaveNoDiff) { EXPECT_EQ(line_diff("a\nb\n", "a\nb\n", "f"), ""); }

TEST(SetupDiff, ShowsRemovedAddedAndKeptLines) {
  EXPECT_EQ(line_diff("a\nb\nc\n", "a\nB\nc\nd\n", "/etc/x"),
            "--- /etc/x (now)\n+++ /etc/x (new)\n a\n-b\n+B\n c\n+d\n");
  EXPECT_EQ(line_diff("", "new\n", "f"), "--- f (now)\n+++ f (new)\n+new\n");
  EXPECT_NE(line_diff("old", "old\n", "f").find("no newline"), std::string::npos);
}

}  // namespace
}  // namespace m2mlat::setup
