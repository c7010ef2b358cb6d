// `setup chrony` as a plan: the configuration and the drop-in as file steps (no command), the same
// chrony.conf step as `setup board`, and applying it into a real folder: written, backed up, then
// nothing to change.
#include "m2mlat/setup/chrony.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/board.hpp"
#include "setup_test_util.hpp"

namespace m2mlat::setup {
namespace {

using testing::TempRoot;

sync::ChronyConfigOptions peer() {
  sync::ChronyConfigOptions o;
  o.mode = sync::SyncMode::co_referenced;
  o.role = sync::SyncRole::peer;
  o.reference = "10.0.0.1";
  return o;
}

TEST(SetupChrony, FilesOnlyTheDropInWithACpu) {
  const auto plan = plan_chrony(peer(), "/etc/chrony/chrony.conf", -1, "/etc/dropin.conf");
  ASSERT_EQ(plan.steps.size(), 1u);
  EXPECT_EQ(plan.steps[0].kind, Step::Kind::file);
  EXPECT_EQ(plan.steps[0].path, "/etc/chrony/chrony.conf");
  EXPECT_EQ(plan.steps[0].content, sync::chrony_config(peer()));
  EXPECT_EQ(plan.steps[0].why, "chrony for the co-referenced mode (peer)");
  EXPECT_NE(plan.notes.at(0).find("chronyd -p -f /etc/chrony/chrony.conf"), std::string::npos);

  const auto pinned = plan_chrony(peer(), "/etc/chrony/chrony.conf", 3, "/etc/dropin.conf");
  ASSERT_EQ(pinned.steps.size(), 2u);
  EXPECT_EQ(pinned.steps[1].path, "/etc/dropin.conf");
  EXPECT_EQ(pinned.steps[1].content, sync::chrony_cpu_dropin(3));
  for (const auto& step : pinned.steps) EXPECT_EQ(step.kind, Step::Kind::file);  // restarts are the user's

  auto no_reference = peer();
  no_reference.reference.clear();
  EXPECT_THROW(plan_chrony(no_reference, "/etc/chrony/chrony.conf", -1, "/etc/dropin.conf"), core::Error);
}

TEST(SetupChrony, TheBoardPlanWritesTheSameChronyConf) {
  BoardSetup board;
  board.agent.role = "vehicle";
  board.agent.node = "vehicle";
  board.agent.chip = "pinctrl-rp1";
  board.agent.line = "GPIO16";
  board.chrony = peer();
  const auto plan = plan_board(board, {});
  const auto conf = chrony_conf_step(peer(), board.chrony_conf);
  bool found = false;
  for (const auto& step : plan.steps)
    if (step.path == board.chrony_conf) {
      found = true;
      EXPECT_EQ(step.content, conf.content);
      EXPECT_EQ(step.why, conf.why);
    }
  EXPECT_TRUE(found);
}

TEST(SetupChrony, AppliedItIsWrittenBackedUpAndThenUnchanged) {
  TempRoot root;
  const std::string conf = "/etc/chrony/chrony.conf";
  root.write(conf, "server old.example.org\n");
  const auto plan = plan_chrony(peer(), conf, 1, "/etc/systemd/system/chrony.service.d/m2mlat-cpu.conf");

  const auto dry = testing::apply_into(plan, root.path(), true);
  EXPECT_NE(dry.text.find("would copy " + root.file(conf) + " to " + root.file(conf) + ".m2mlat-backup"),
            std::string::npos)
      << dry.text;
  EXPECT_EQ(root.read(conf), "server old.example.org\n");

  const auto first = testing::apply_into(plan, root.path());
  EXPECT_EQ(first.result.changes, 2);
  EXPECT_NE(first.text.find("\nwriting " + root.file(conf)), std::string::npos) << first.text;
  EXPECT_EQ(root.read(conf), sync::chrony_config(peer()));
  EXPECT_EQ(root.read(conf + ".m2mlat-backup"), "server old.example.org\n");
  EXPECT_EQ(root.read("/etc/systemd/system/chrony.service.d/m2mlat-cpu.conf"), sync::chrony_cpu_dropin(1));

  const auto second = testing::apply_into(plan, root.path());
  EXPECT_EQ(second.result.changes, 0);
  EXPECT_NE(second.text.find(root.file(conf) + ": unchanged"), std::string::npos);
}

}  // namespace
}  // namespace m2mlat::setup
