// CPU lists, capability masks, and the settings' outcomes on this machine.
#include "m2mlat/rt/scheduling.hpp"

#include <gtest/gtest.h>

namespace m2mlat::rt {
namespace {

TEST(CpuList, ParsesRangesAndSingles) {
  std::vector<int> cpus;
  ASSERT_TRUE(parse_cpu_list("0-3,6\n", cpus));
  EXPECT_EQ(cpus, (std::vector<int>{0, 1, 2, 3, 6}));
  ASSERT_TRUE(parse_cpu_list("2", cpus));
  EXPECT_EQ(cpus, std::vector<int>{2});
  EXPECT_FALSE(parse_cpu_list("", cpus));
  EXPECT_FALSE(parse_cpu_list("3-1", cpus));
  EXPECT_FALSE(parse_cpu_list("a", cpus));
}

TEST(Capabilities, ReadsTheEffectiveMask) {
  const std::string root = "Name:\tx\nCapInh:\t0000000000000000\nCapEff:\t000001ffffffffff\n";
  EXPECT_TRUE(status_has_capability(root, kCapSysNice));
  EXPECT_TRUE(status_has_capability(root, kCapIpcLock));
  const std::string user = "CapEff:\t0000000000800000\n";  // only bit 23
  EXPECT_TRUE(status_has_capability(user, kCapSysNice));
  EXPECT_FALSE(status_has_capability(user, kCapIpcLock));
  EXPECT_FALSE(status_has_capability("no such field", kCapSysNice));
}

TEST(Scheduling, OutOfRangeRequestsAreRefusedWithAReason) {
  const auto fifo = set_fifo_priority(1000);
  EXPECT_FALSE(fifo.ok);
  EXPECT_NE(fifo.message.find("out of range"), std::string::npos);
  const auto cpu = set_cpu_affinity(-1);
  EXPECT_FALSE(cpu.ok);
  EXPECT_NE(cpu.message.find("CPU -1"), std::string::npos);
}

TEST(Scheduling, PinningToAnAllowedCpuWorks) {
  const auto cpus = allowed_cpus();
  ASSERT_FALSE(cpus.empty());
  const auto outcome = set_cpu_affinity(cpus.front());
  EXPECT_TRUE(outcome.ok) << outcome.message;
  EXPECT_EQ(allowed_cpus(), std::vector<int>{cpus.front()});
}

}  // namespace
}  // namespace m2mlat::rt
