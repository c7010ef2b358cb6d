// `m2mlat setup gpio`: access to the GPIO character devices without root. A udev rule gives the
// group gpio read/write on /dev/gpiochip* (the same rule the Debian package installs:
// packaging/60-m2mlat-gpio.rules, checked equal by tests/unit/setup/gpio_test.cpp), the group is
// created if the system has none (Raspberry Pi OS has one), and a user is added to it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/setup/plan.hpp"

namespace m2mlat::setup {

// The rule's text, and where an administrator's copy goes (/etc/udev/rules.d overrides the package's
// /usr/lib/udev/rules.d file of the same name, so installing both is harmless).
extern const std::string_view kGpioUdevRule;
inline constexpr std::string_view kGpioUdevRulePath = "/etc/udev/rules.d/60-m2mlat-gpio.rules";
inline constexpr std::string_view kGpioGroup = "gpio";

struct GpioSetup {
  std::vector<std::string> users;  // to add to the group (e.g. the login that runs `m2mlat record`)
};

// The members of `group` in the text of /etc/group, or false when the group is not there.
bool group_members(std::string_view etc_group, std::string_view group, std::vector<std::string>& members);

// The plan, given the current /etc/group text: the rule (then udevadm reload and trigger when it
// changed), groupadd when the group is missing, usermod -aG for each user not yet a member.
Plan plan_gpio(const GpioSetup& setup, std::string_view etc_group);

}  // namespace m2mlat::setup
