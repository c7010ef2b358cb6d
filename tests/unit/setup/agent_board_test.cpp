// setup agent and setup board: the agent's configuration is one `m2mlat record --config` accepts,
// with the board's role; the board plan holds every part, writes the shared env file once, and a
// second run into the same root changes nothing.
#include <gtest/gtest.h>

#include "m2mlat/capture/record_config.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/agent_config.hpp"
#include "m2mlat/setup/board.hpp"
#include "m2mlat/setup/gpio.hpp"
#include "m2mlat/sync/chrony_config.hpp"
#include "setup_test_util.hpp"

namespace m2mlat::setup {
namespace {

AgentSetup vehicle() {
  AgentSetup a;
  a.role = "vehicle";
  a.node = "vehicle";
  a.chip = "pinctrl-rp1";
  a.line = "GPIO16";
  return a;
}

TEST(SetupAgent, ConfigIsARecordConfigWithTheRole) {
  auto a = vehicle();
  a.rt_priority = 80;
  a.cpu = 3;
  const auto config = capture::parse_record_config(agent_config_toml(a), "vehicle.toml");
  EXPECT_EQ(config.node, "vehicle");
  EXPECT_EQ(config.role, core::Role::effect);
  EXPECT_EQ(config.source, "gpio");
  ASSERT_EQ(config.channels.size(), 1u);
  EXPECT_EQ(config.channels[0].name, "wheel");
  EXPECT_EQ(config.channels[0].chip, "pinctrl-rp1");
  EXPECT_EQ(config.channels[0].line, "GPIO16");
  EXPECT_EQ(config.channels[0].refractory, std::chrono::milliseconds(10));
  EXPECT_EQ(config.rt_priority, 80);
  EXPECT_EQ(config.cpu, 3);

  a.role = "operator";
  a.node = "operator";
  EXPECT_EQ(capture::parse_record_config(agent_config_toml(a), "operator.toml").role, core::Role::cause);
}

TEST(SetupAgent, RejectsBadInput) {
  auto a = vehicle();
  a.role = "driver";
  EXPECT_THROW(agent_config_toml(a), core::Error);
  a = vehicle();
  a.node = "../x";
  EXPECT_THROW(agent_config_toml(a), core::Error);
  a = vehicle();
  a.chip = "pinctrl\"rp1";
  EXPECT_THROW(agent_config_toml(a), core::Error);
  a = vehicle();
  a.listen = "0.0.0.0:8470";  // beyond loopback without a token
  EXPECT_THROW(agent_env_keys(a), core::Error);
  a.token_file = "/etc/m2mlat/token";
  EXPECT_EQ(agent_env_keys(a), (EnvKeys{{"M2MLAT_LISTEN", "0.0.0.0:8470"},
                                        {"M2MLAT_AGENT_ARGS", "\"--token-file /etc/m2mlat/token\""}}));
}

TEST(SetupAgent, PlanPrintsTheStartCommand) {
  const auto plan = plan_agent(vehicle(), "");
  ASSERT_EQ(plan.steps.size(), 1u);  // no env keys: the unit's defaults
  EXPECT_EQ(plan.steps[0].path, "/etc/m2mlat/vehicle.toml");
  bool start = false;
  for (const auto& n : plan.notes) start |= n == "start it: systemctl enable --now m2mlat-agent@vehicle";
  EXPECT_TRUE(start);
}

BoardSetup vehicle_board() {
  BoardSetup b;
  b.agent = vehicle();
  b.agent.listen = "10.0.0.2:8470";
  b.agent.token_file = "/etc/m2mlat/token";
  b.chrony.mode = sync::SyncMode::co_referenced;
  b.chrony.reference = "10.0.0.1";
  b.chrony_core = 1;
  b.irq_core = 2;
  b.users = {"pi"};
  return b;
}

constexpr std::string_view kWheelInterrupts =
    "           CPU0       CPU1\n183:  12  0  pinctrl-rp1  16 Edge      m2mlat-wheel\n";

TEST(SetupBoard, PlanHasEveryPart) {
  const auto plan = plan_board(vehicle_board(), BoardState{"gpio:x:997:\n", std::string(kWheelInterrupts), ""});
  std::vector<std::string> files;
  for (const auto& s : plan.steps)
    if (s.kind == Step::Kind::file) files.push_back(s.path);
  EXPECT_EQ(files, (std::vector<std::string>{std::string(kGpioUdevRulePath), "/etc/chrony/chrony.conf",
                                             std::string(sync::kChronyDropinPath), "/etc/m2mlat/vehicle.toml",
                                             "/etc/m2mlat/vehicle.env", "/proc/irq/183/smp_affinity_list"}));
  // The vehicle follows the operator's board: chrony's text is the chrony part's own for a peer.
  sync::ChronyConfigOptions peer;
  peer.role = sync::SyncRole::peer;
  peer.reference = "10.0.0.1";
  EXPECT_EQ(plan.steps[4].content, sync::chrony_config(peer));
  // One env file with the agent's and the IRQ's keys.
  const auto& env = plan.steps[plan.steps.size() - 2].content;
  EXPECT_NE(env.find("M2MLAT_LISTEN=10.0.0.2:8470\n"), std::string::npos);
  EXPECT_NE(env.find("M2MLAT_IRQ_CPU=2\nM2MLAT_IRQ_NAME=m2mlat-wheel\n"), std::string::npos);
}

TEST(SetupBoard, PeerWithoutReferenceIsAUsageError) {
  auto b = vehicle_board();
  b.chrony.reference.clear();
  EXPECT_THROW(plan_board(b, BoardState{}), core::Error);
  b.sync_role = "reference";  // serving instead needs --allow
  EXPECT_THROW(plan_board(b, BoardState{}), core::Error);
  b.chrony.allow = {"10.0.0.0/24"};
  EXPECT_NO_THROW(plan_board(b, BoardState{}));
}

TEST(SetupBoard, SecondRunChangesNothing) {
  testing::TempRoot root;
  root.write("/etc/m2mlat/vehicle.env", "# mine\nM2MLAT_LISTEN=127.0.0.1:8470\n");
  root.write("/proc/irq/183/smp_affinity_list", "0-3\n");
  const auto state = [&] {
    return BoardState{"gpio:x:997:pi\n", std::string(kWheelInterrupts), root.read("/etc/m2mlat/vehicle.env")};
  };
  const auto first = testing::apply_into(plan_board(vehicle_board(), state()), root.path());
  EXPECT_EQ(first.result.files_checked, 6);
  EXPECT_GE(first.result.changes, 6);
  EXPECT_NE(first.text.find("-M2MLAT_LISTEN=127.0.0.1:8470"), std::string::npos);  // the diff
  EXPECT_NE(first.text.find("+M2MLAT_LISTEN=10.0.0.2:8470"), std::string::npos);
  EXPECT_EQ(root.read("/etc/m2mlat/vehicle.env.m2mlat-backup"), "# mine\nM2MLAT_LISTEN=127.0.0.1:8470\n");
  EXPECT_EQ(root.read("/proc/irq/183/smp_affinity_list"), "2\n");
  const auto second = testing::apply_into(plan_board(vehicle_board(), state()), root.path());
  EXPECT_EQ(second.result.changes, 0) << second.text;
  EXPECT_NE(second.text.find("nothing to change"), std::string::npos);
}

}  // namespace
}  // namespace m2mlat::setup
