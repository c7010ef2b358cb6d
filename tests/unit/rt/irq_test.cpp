// /proc/interrupts parsing and IRQ routing against fixture text and a temporary /proc tree.
#include "m2mlat/rt/irq.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "temp_dir.hpp"

namespace m2mlat::rt {
namespace {

constexpr std::string_view kInterrupts =
    "           CPU0       CPU1       CPU2       CPU3       \n"
    "  9:          0          0          0          0     GICv2  25 Level     vgic\n"
    " 11:      12345        678         90          1     GICv2  30 Level     arch_timer\n"
    "155:          7          0          0          0  pinctrl-rp1  16 Edge      m2mlat-wheel\n"
    "156:          0          3          0          0  pinctrl-rp1  17 Edge      m2mlat-wheel2\n"
    "160:          1          2          3          4   PCI-MSI 1-edge      eth0-rx, eth0-tx\n"
    "IPI0:       100        200        300        400       Rescheduling interrupts\n"
    "Err:          0\n";

TEST(Interrupts, ParsesNumberedRowsWithCountsAndActions) {
  const auto lines = parse_interrupts(kInterrupts);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[1].irq, 11);
  EXPECT_EQ(lines[1].counts, (std::vector<std::uint64_t>{12345, 678, 90, 1}));
  EXPECT_EQ(lines[2].irq, 155);
  EXPECT_EQ(lines[2].description, "pinctrl-rp1  16 Edge      m2mlat-wheel");
  EXPECT_EQ(lines[2].actions, std::vector<std::string>{"m2mlat-wheel"});
  EXPECT_EQ(lines[4].actions, (std::vector<std::string>{"eth0-rx", "eth0-tx"}));
}

TEST(Interrupts, FindsTheIrqByTheExactConsumerLabel) {
  EXPECT_EQ(find_irq_in_interrupts(kInterrupts, "m2mlat-wheel"), std::vector<int>{155});
  EXPECT_EQ(find_irq_in_interrupts(kInterrupts, "m2mlat-wheel2"), std::vector<int>{156});
  EXPECT_EQ(find_irq_in_interrupts(kInterrupts, "eth0-tx"), std::vector<int>{160});
  EXPECT_TRUE(find_irq_in_interrupts(kInterrupts, "m2mlat").empty());
  EXPECT_TRUE(find_irq_in_interrupts(kInterrupts, "Edge").empty());
}

TEST(Interrupts, PinWritesTheCpuAndReadsItBack) {
  const m2mlat::testing::TempDir temp;  // stands for /proc
  const auto& root = temp.path();
  std::filesystem::create_directories(root / "irq" / "155");
  std::ofstream(root / "irq" / "155" / "smp_affinity_list") << "0-3\n";
  EXPECT_EQ(irq_affinity(155, root.string()), "0-3");
  const auto outcome = pin_irq(155, 2, root.string());
  EXPECT_TRUE(outcome.ok) << outcome.message;
  EXPECT_EQ(irq_affinity(155, root.string()), "2");
  const auto missing = pin_irq(999, 2, root.string());
  EXPECT_FALSE(missing.ok);
  EXPECT_NE(missing.message.find("999"), std::string::npos);
  EXPECT_FALSE(irq_affinity(999, root.string()).has_value());
}

}  // namespace
}  // namespace m2mlat::rt
