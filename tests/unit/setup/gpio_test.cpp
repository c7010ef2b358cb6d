// setup gpio: the rule is the package's, the group and the user are added only when missing, and a
// second run into the same root changes nothing.
#include "m2mlat/setup/gpio.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "setup_test_util.hpp"

namespace m2mlat::setup {
namespace {

using testing::TempRoot;

std::vector<std::string> command_lines(const Plan& plan) {
  std::vector<std::string> lines;
  for (const auto& s : plan.steps)
    if (s.kind == Step::Kind::command) {
      std::string line;
      for (const auto& a : s.argv) line += (line.empty() ? "" : " ") + a;
      lines.push_back(line);
    }
  return lines;
}

TEST(SetupGpio, RuleIsThePackagesRule) {
  std::ifstream in(std::string(M2MLAT_TEST_DATA) + "/../../packaging/60-m2mlat-gpio.rules");
  ASSERT_TRUE(in) << "packaging/60-m2mlat-gpio.rules";
  std::ostringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), kGpioUdevRule);
}

TEST(SetupGpio, GroupMembers) {
  const std::string etc_group = "root:x:0:\ngpio:x:997:pi,m2mlat\nvideo:x:44:\n";
  std::vector<std::string> members;
  ASSERT_TRUE(group_members(etc_group, "gpio", members));
  EXPECT_EQ(members, (std::vector<std::string>{"pi", "m2mlat"}));
  ASSERT_TRUE(group_members(etc_group, "video", members));
  EXPECT_TRUE(members.empty());
  EXPECT_FALSE(group_members(etc_group, "gpi", members));
}

TEST(SetupGpio, AddsMissingGroupAndUser) {
  const auto plan = plan_gpio(GpioSetup{{"pi"}}, "root:x:0:\n");
  EXPECT_EQ(plan.steps.front().path, kGpioUdevRulePath);
  EXPECT_EQ(command_lines(plan),
            (std::vector<std::string>{"udevadm control --reload-rules",
                                      "udevadm trigger --subsystem-match=gpio --action=change",
                                      "groupadd --system gpio", "usermod -aG gpio pi"}));
  // The udev commands run only after the rule changed.
  EXPECT_EQ(plan.steps[1].after, kGpioUdevRulePath);
  EXPECT_EQ(plan.steps[3].after, "");
}

TEST(SetupGpio, NothingForAnExistingGroupAndMember) {
  const auto plan = plan_gpio(GpioSetup{{"pi"}}, "gpio:x:997:pi\n");
  EXPECT_EQ(command_lines(plan).size(), 2u);  // the udev reload pair, conditional on the rule
  EXPECT_THROW(plan_gpio(GpioSetup{{"bad user"}}, ""), core::Error);
}

TEST(SetupGpio, SecondRunChangesNothing) {
  TempRoot root;
  const auto plan = plan_gpio(GpioSetup{{"pi"}}, "gpio:x:997:pi\n");
  const auto dry = testing::apply_into(plan, root.path(), true);
  EXPECT_EQ(dry.result.changes, 3);  // the rule and the two udev commands
  EXPECT_NE(dry.text.find("would write"), std::string::npos);
  EXPECT_NE(dry.text.find("KERNEL==\"gpiochip[0-9]*\""), std::string::npos);  // the full content
  EXPECT_NE(dry.text.find("would run: udevadm control --reload-rules"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(root.file(std::string(kGpioUdevRulePath))));

  const auto first = testing::apply_into(plan, root.path());
  EXPECT_EQ(first.result.changes, 3);
  EXPECT_EQ(root.read(std::string(kGpioUdevRulePath)), kGpioUdevRule);
  EXPECT_NE(first.text.find("not run under --root"), std::string::npos);

  const auto second = testing::apply_into(plan, root.path());
  EXPECT_EQ(second.result.changes, 0);
  EXPECT_NE(second.text.find("nothing to change"), std::string::npos);
}

}  // namespace
}  // namespace m2mlat::setup
