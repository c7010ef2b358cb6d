// `m2mlat setup board`: everything one board of the rig needs, in one plan: GPIO permissions
// (gpio.hpp), chrony for the synchronisation mode (chrony.hpp, as `setup chrony`) and
// optionally chronyd on its own core (pin_chrony.hpp), the agent's configuration (agent_config.hpp),
// and the wheel line's interrupt on a chosen core (irq.hpp). The agent's and the IRQ's keys share the
// node's env file, so the board plan writes that file once with both.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/setup/agent_config.hpp"
#include "m2mlat/setup/plan.hpp"
#include "m2mlat/sync/chrony_config.hpp"

namespace m2mlat::setup {

struct BoardSetup {
  AgentSetup agent;                  // role, node, chip, line, listen, token ...
  sync::ChronyConfigOptions chrony;  // mode, and per mode reference / allow / servers ...
  std::string sync_role;             // co-referenced: reference | peer; "" = operator serves, vehicle follows
  std::string chrony_conf = "/etc/chrony/chrony.conf";
  int chrony_core = -1;            // pin chronyd here; -1 = leave it
  int irq_core = -1;               // route the wheel line's IRQ here; -1 = leave it
  std::vector<std::string> users;  // added to the group gpio
};

// The chrony role a board takes in co-referenced mode when none is given: the operator's board
// serves its clock, the vehicle's follows it.
sync::SyncRole default_sync_role(std::string_view board_role);

// The current state of the files the plan depends on ("" when missing).
struct BoardState {
  std::string etc_group, interrupts, env;
};

Plan plan_board(BoardSetup setup, const BoardState& state);

}  // namespace m2mlat::setup
