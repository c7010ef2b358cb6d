// The doctor's verdicts on made-up machines.
#include "m2mlat/setup/doctor.hpp"

#include <gtest/gtest.h>
#include <sys/timex.h>

#include <cerrno>

#include "m2mlat/capture/fake_gpio.hpp"

namespace m2mlat::setup {
namespace {

DoctorInputs healthy(const capture::GpioDevices& devices) {
  DoctorInputs in;
  in.devices = &devices;
  in.kernel_release = "6.6.51+rpt-rpi-2712";
  in.privileges.cap_sys_nice = true;
  in.privileges.cap_ipc_lock = true;
  in.clock.available = true;
  in.clock.synchronised = true;
  in.clock.max_error_ns = 20'000;
  in.clock.est_error_ns = 5'000;
  in.irq_writable = true;
  return in;
}

const Finding* find(const DoctorReport& report, const std::string& check, Status status) {
  for (const auto& f : report.findings)
    if (f.check == check && f.status == status) return &f;
  return nullptr;
}

TEST(Doctor, AMachineWithoutGpioIsToldSoButNeedsNoFixing) {
  capture::FakeGpio none;
  const auto report = run_doctor(healthy(none));
  EXPECT_FALSE(report.needs_fixing());
  EXPECT_NE(find(report, "gpio", Status::warn), nullptr);
  EXPECT_TRUE(report.chips.empty());
}

TEST(Doctor, ListsLinesWithConsumersAndTheIrqsRouting) {
  capture::FakeGpio gpio;
  const auto path = gpio.add_chip("pinctrl-rp1", 4, {"GPIO0", "GPIO1", "GPIO2", "GPIO3"});
  gpio.hold_line(path, 2, "m2mlat-wheel");
  auto in = healthy(gpio);
  in.interrupts_text = "      CPU0  CPU1\n 155:  7  0  pinctrl-rp1  2 Edge  m2mlat-wheel\n";
  in.irq_affinity = [](int irq) { return irq == 155 ? std::optional<std::string>("3") : std::nullopt; };
  const auto report = run_doctor(in);
  EXPECT_FALSE(report.needs_fixing());
  ASSERT_EQ(report.chips.size(), 1u);
  ASSERT_EQ(report.chips[0].lines.size(), 4u);
  EXPECT_EQ(report.chips[0].lines[2].consumer, "m2mlat-wheel");
  const auto* irq = find(report, "irq", Status::ok);
  ASSERT_NE(irq, nullptr);
  EXPECT_EQ(irq->detail, "IRQ 155 (m2mlat-wheel) is routed to CPU(s) 3");
}

TEST(Doctor, WhatNeedsFixingIsSaid) {
  capture::FakeGpio gpio;
  const auto path = gpio.add_chip("pinctrl-rp1", 4);
  gpio.deny_access(path);
  auto in = healthy(gpio);
  in.kernel_release = "5.10.103-v7l+";
  in.clock.synchronised = false;
  in.privileges = {};
  in.irq_writable = false;
  const auto report = run_doctor(in);
  EXPECT_TRUE(report.needs_fixing());
  const auto* permissions = find(report, "permissions", Status::fail);
  ASSERT_NE(permissions, nullptr);
  EXPECT_NE(permissions->fix.find("udev"), std::string::npos);
  EXPECT_NE(find(report, "kernel", Status::fail), nullptr);
  EXPECT_NE(find(report, "clock", Status::fail), nullptr);
  const auto* fifo = find(report, "realtime", Status::warn);
  ASSERT_NE(fifo, nullptr);
  EXPECT_NE(fifo->fix.find("rtprio"), std::string::npos);
  EXPECT_NE(find(report, "irq", Status::warn), nullptr);
  EXPECT_FALSE(report.chips[0].error.empty());
}

TEST(Doctor, TheKernelClocksBoundsAreShownInMicroseconds) {
  capture::FakeGpio none;
  const auto report = run_doctor(healthy(none));
  const auto* clock = find(report, "clock", Status::ok);
  ASSERT_NE(clock, nullptr);
  EXPECT_EQ(clock->detail, "clock synchronised: estimated error 5 us, maximum error 20 us");
  auto in = healthy(none);
  in.clock = sync::kernel_clock_state({}, -1, EPERM);  // the call failed
  EXPECT_NE(find(run_doctor(in), "clock", Status::warn), nullptr);
}

TEST(Doctor, KernelVersions) {
  int major = 0, minor = 0;
  ASSERT_TRUE(parse_kernel_version("6.1.0-56-amd64", major, minor));
  EXPECT_EQ(major, 6);
  EXPECT_EQ(minor, 1);
  EXPECT_FALSE(parse_kernel_version("unknown", major, minor));
}

}  // namespace
}  // namespace m2mlat::setup
