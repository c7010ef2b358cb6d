// setup::replace_file: the backup of a replaced system file, on top of the output-file writer.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>

#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/apply.hpp"
#include "setup_test_util.hpp"

namespace fs = std::filesystem;
using namespace m2mlat;
using setup::testing::TempRoot;

namespace {
mode_t mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::lstat(path.c_str(), &st), 0) << path;
  return st.st_mode;
}
}  // namespace

TEST(ReplaceFile, BacksUpTheOldFileWithItsMode) {
  TempRoot root;
  root.write("/etc/chrony/chrony.conf", "old\n");
  const auto target = root.file("/etc/chrony/chrony.conf");
  ASSERT_EQ(::chmod(target.c_str(), 0600), 0);
  setup::replace_file(target, "new\n", 0644);
  EXPECT_EQ(root.read("/etc/chrony/chrony.conf"), "new\n");
  EXPECT_EQ(mode_of(target) & 07777, 0644u);
  EXPECT_EQ(root.read("/etc/chrony/chrony.conf.m2mlat-backup"), "old\n");
  EXPECT_EQ(mode_of(target + ".m2mlat-backup") & 07777, 0600u);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(fs::path(target).parent_path())) ++files;
  EXPECT_EQ(files, 2u);  // no temporary left behind
}

TEST(ReplaceFile, NewFileInANewFolderHasNoBackup) {
  TempRoot root;
  const auto target = root.file("/etc/systemd/system/chrony.service.d/m2mlat-cpu.conf");
  setup::replace_file(target, "[Service]\n", 0644);
  EXPECT_EQ(root.read("/etc/systemd/system/chrony.service.d/m2mlat-cpu.conf"), "[Service]\n");
  EXPECT_FALSE(fs::exists(target + ".m2mlat-backup"));
}

TEST(ReplaceFile, SymlinkTargetRefusedAndNothingChanged) {
  TempRoot root;
  root.write("/victim", "precious\n");
  fs::create_directories(root.file("/etc"));
  fs::create_symlink(root.file("/victim"), root.file("/etc/chrony.conf"));
  try {
    setup::replace_file(root.file("/etc/chrony.conf"), "new\n", 0644);
    FAIL() << "written through a symlink";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("a symbolic link"), std::string::npos) << e.what();
  }
  EXPECT_EQ(root.read("/victim"), "precious\n");
  EXPECT_TRUE(fs::is_symlink(root.file("/etc/chrony.conf")));
  EXPECT_FALSE(fs::exists(root.file("/etc/chrony.conf.m2mlat-backup")));
}

// A link planted as the backup's name cannot make the backup overwrite another file.
TEST(ReplaceFile, SymlinkedBackupRefusedAndTargetKept) {
  TempRoot root;
  root.write("/victim", "precious\n");
  root.write("/etc/chrony.conf", "old\n");
  fs::create_symlink(root.file("/victim"), root.file("/etc/chrony.conf.m2mlat-backup"));
  EXPECT_THROW(setup::replace_file(root.file("/etc/chrony.conf"), "new\n", 0644), core::Error);
  EXPECT_EQ(root.read("/victim"), "precious\n");
  EXPECT_EQ(root.read("/etc/chrony.conf"), "old\n");
}

// apply_plan shows the file it replaces: a hostile byte in it is shown escaped, not sent to the
// terminal; the file is still backed up and replaced.
TEST(ReplaceFile, ApplyShowsTheOldContentEscaped) {
  TempRoot root;
  root.write("/etc/m2mlat/agent.toml", "node = \"op\x1b]0;owned\x07\"\n");
  setup::Plan plan;
  plan.part = "agent";
  plan.steps.push_back(
      setup::file_step("/etc/m2mlat/agent.toml", "node = \"operator\"\n", "the agent's configuration"));
  const auto applied = setup::testing::apply_into(plan, root.path());
  EXPECT_EQ(applied.text.find('\x1b'), std::string::npos) << applied.text;
  EXPECT_NE(applied.text.find("op\\x1b]0;owned\\x07"), std::string::npos) << applied.text;
  EXPECT_EQ(root.read("/etc/m2mlat/agent.toml"), "node = \"operator\"\n");
  EXPECT_EQ(root.read("/etc/m2mlat/agent.toml.m2mlat-backup"), "node = \"op\x1b]0;owned\x07\"\n");
}
