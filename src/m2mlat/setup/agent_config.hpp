// `m2mlat setup agent`: the configuration of one board's agent (m2mlat-agent@<node>.service):
//   /etc/m2mlat/<node>.toml  what `m2mlat agent --config` reads (the keys of `m2mlat record --config`,
//                            capture/record_config.hpp): node, role, the wheel channel, [rt];
//   /etc/m2mlat/<node>.env   where it listens and its further options (M2MLAT_LISTEN,
//                            M2MLAT_AGENT_ARGS=--token-file F), read by the unit.
// The role is the board's place in the rig: operator (its wheel is the cause) or vehicle (effect).
// Starting the agent is left to the administrator: the plan's note gives the systemctl command.
#pragma once

#include <string>
#include <string_view>

#include "m2mlat/setup/env_file.hpp"
#include "m2mlat/setup/plan.hpp"

namespace m2mlat::setup {

struct AgentSetup {
  std::string role;  // operator | vehicle
  std::string node;  // the board's name: file names, unit instance, stores, reports
  std::string chip;  // name, label (pinctrl-rp1) or path
  std::string line;  // offset or name (GPIO16)
  std::string channel = "wheel";
  std::string edges = "falling";  // the A3144 pulls low when the magnet arrives
  std::string bias = "pull-up";
  std::string refractory = "10ms";
  std::string source = "gpio";  // gpio; sim to try the whole chain without a sensor
  std::string listen;           // HOST:PORT; "" = the unit's default (127.0.0.1:8470)
  std::string token_file;       // needed when listening beyond loopback
  int rt_priority = 0;          // SCHED_FIFO priority of the capture thread; 0 = none
  int cpu = -1;                 // CPU of the capture thread; -1 = any
};

// "cause" for operator, "effect" for vehicle; core::Error(usage) otherwise.
std::string_view agent_role(std::string_view role);
// The TOML text of /etc/m2mlat/<node>.toml.
std::string agent_config_toml(const AgentSetup& setup);
// The env keys (M2MLAT_LISTEN, M2MLAT_AGENT_ARGS) the setup sets; none when it sets nothing.
EnvKeys agent_env_keys(const AgentSetup& setup);
std::string agent_config_path(std::string_view node);
std::string agent_unit(std::string_view node);  // m2mlat-agent@<node>

// The plan, given the node's current env file ("" if none): the TOML file, the env file when it has
// keys to set, and notes with the command that starts the agent.
Plan plan_agent(const AgentSetup& setup, std::string_view current_env);

}  // namespace m2mlat::setup
