// The GPIO permissions part of `m2mlat setup` (gpio.hpp).
#include "m2mlat/setup/gpio.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/names.hpp"

namespace m2mlat::setup {

// Byte for byte the package's packaging/60-m2mlat-gpio.rules (a unit test compares them).
const std::string_view kGpioUdevRule =
    "# GPIO character devices for the group gpio (as Raspberry Pi OS does), so that the m2mlat agent runs "
    "as\n"
    "# an unprivileged user in that group. Installed by the m2mlat package; the group is created by its\n"
    "# postinst if the system has none.\n"
    "SUBSYSTEM==\"gpio\", KERNEL==\"gpiochip[0-9]*\", GROUP=\"gpio\", MODE=\"0660\"\n";

bool group_members(std::string_view etc_group, std::string_view group, std::vector<std::string>& members) {
  std::size_t pos = 0;
  while (pos < etc_group.size()) {
    auto end = etc_group.find('\n', pos);
    if (end == std::string_view::npos) end = etc_group.size();
    const auto line = etc_group.substr(pos, end - pos);
    pos = end + 1;
    // name:password:gid:member,member
    const auto c1 = line.find(':');
    if (c1 == std::string_view::npos || line.substr(0, c1) != group) continue;
    const auto c3 = line.find(':', line.find(':', c1 + 1) + 1);
    members.clear();
    if (c3 == std::string_view::npos) return true;
    auto rest = line.substr(c3 + 1);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      const auto name = rest.substr(0, comma);
      if (!name.empty()) members.emplace_back(name);
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    return true;
  }
  return false;
}

Plan plan_gpio(const GpioSetup& setup, std::string_view etc_group) {
  for (const auto& user : setup.users) check_name("--user", user);
  Plan plan;
  plan.part = "gpio";
  const std::string rule_path(kGpioUdevRulePath);
  plan.steps.push_back(file_step(rule_path, std::string(kGpioUdevRule),
                                 "udev rule: /dev/gpiochip* for the group gpio, mode 0660"));
  plan.steps.push_back(
      command_step({"udevadm", "control", "--reload-rules"}, "udev reads the new rule", rule_path));
  plan.steps.push_back(command_step({"udevadm", "trigger", "--subsystem-match=gpio", "--action=change"},
                                    "the existing chips get the group", rule_path));
  std::vector<std::string> members;
  const bool has_group = group_members(etc_group, kGpioGroup, members);
  if (!has_group)
    plan.steps.push_back(
        command_step({"groupadd", "--system", std::string(kGpioGroup)}, "the group is missing"));
  for (const auto& user : setup.users) {
    if (std::find(members.begin(), members.end(), user) != members.end()) continue;
    plan.steps.push_back(command_step({"usermod", "-aG", std::string(kGpioGroup), user},
                                      fmt::format("{} is not in the group gpio", user)));
    plan.notes.push_back(fmt::format("{} gets the group at the next login (log out and in again)", user));
  }
  return plan;
}

}  // namespace m2mlat::setup
