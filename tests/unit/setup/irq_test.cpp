// setup irq: the line's IRQ found by its consumer label or its chip row, the in-place write of
// smp_affinity_list, and the env keys that keep it.
#include "m2mlat/setup/irq.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "setup_test_util.hpp"

namespace m2mlat::setup {
namespace {

// A Raspberry Pi 5 like /proc/interrupts: GPIO16 held by the agent (consumer m2mlat-wheel), GPIO21
// by another program.
constexpr std::string_view kInterrupts =
    "           CPU0       CPU1       CPU2       CPU3\n"
    "  9:          0          0          0          0     GICv2  25 Level     vgic\n"
    "183:         12          0          0          0  pinctrl-rp1  16 Edge      m2mlat-wheel\n"
    "188:          3          0          0          0  pinctrl-rp1  21 Edge      other\n"
    "IPI0:       100        100        100        100       Rescheduling interrupts\n";

TEST(SetupIrq, FindsTheLineByConsumerOrChipRow) {
  EXPECT_EQ(find_line_irqs(kInterrupts, IrqSetup{"pinctrl-rp1", "GPIO16", "wheel", 2, {}}),
            std::vector<int>{183});
  // Channel 'pulse' is not held: the chip row of line 21 is found instead.
  EXPECT_EQ(find_line_irqs(kInterrupts, IrqSetup{"pinctrl-rp1", "21", "pulse", 2, {}}),
            std::vector<int>{188});
  EXPECT_EQ(find_line_irqs(kInterrupts, IrqSetup{"/dev/pinctrl-rp1", "GPIO21", "pulse", 2, {}}),
            std::vector<int>{188});
  EXPECT_TRUE(find_line_irqs(kInterrupts, IrqSetup{"pinctrl-rp1", "GPIO5", "pulse", 2, {}}).empty());
}

TEST(SetupIrq, PlanWritesAffinityAndEnv) {
  const auto plan =
      plan_irq(IrqSetup{"pinctrl-rp1", "GPIO16", "wheel", 2, "vehicle"}, kInterrupts, "OTHER=1\n");
  ASSERT_EQ(plan.steps.size(), 2u);
  EXPECT_EQ(plan.steps[0].path, "/proc/irq/183/smp_affinity_list");
  EXPECT_EQ(plan.steps[0].content, "2\n");
  EXPECT_TRUE(plan.steps[0].in_place);
  EXPECT_EQ(plan.steps[1].path, "/etc/m2mlat/vehicle.env");
  EXPECT_EQ(plan.steps[1].content, "OTHER=1\nM2MLAT_IRQ_CPU=2\nM2MLAT_IRQ_NAME=m2mlat-wheel\n");
  EXPECT_THROW(plan_irq(IrqSetup{"c", "1", "wheel", -1, {}}, kInterrupts, ""), core::Error);
  EXPECT_THROW(plan_irq(IrqSetup{"c", "1", "wheel", 1, "../etc"}, kInterrupts, ""), core::Error);
}

TEST(SetupIrq, NotHeldLineOnlyKeepsTheSetting) {
  const auto plan = plan_irq(IrqSetup{"pinctrl-rp1", "GPIO5", "wheel5", 3, {}}, kInterrupts, "");
  EXPECT_TRUE(plan.steps.empty());
  ASSERT_EQ(plan.notes.size(), 2u);
  EXPECT_NE(plan.notes[0].find("no interrupt named 'm2mlat-wheel5'"), std::string::npos);
}

TEST(SetupIrq, AppliesInPlaceAndOnlyOnce) {
  testing::TempRoot root;
  root.write("/proc/irq/183/smp_affinity_list", "0-3\n");
  const auto plan = plan_irq(IrqSetup{"pinctrl-rp1", "GPIO16", "wheel", 2, "vehicle"}, kInterrupts, "");
  const auto first = testing::apply_into(plan, root.path());
  EXPECT_EQ(first.result.changes, 2);
  EXPECT_NE(first.text.find("was: 0-3"), std::string::npos);
  EXPECT_EQ(root.read("/proc/irq/183/smp_affinity_list"), "2\n");
  EXPECT_FALSE(std::filesystem::exists(root.file("/proc/irq/183/smp_affinity_list.m2mlat-backup")));
  const auto again = plan_irq(IrqSetup{"pinctrl-rp1", "GPIO16", "wheel", 2, "vehicle"}, kInterrupts,
                              root.read("/etc/m2mlat/vehicle.env"));
  EXPECT_EQ(testing::apply_into(again, root.path()).result.changes, 0);
}

}  // namespace
}  // namespace m2mlat::setup
