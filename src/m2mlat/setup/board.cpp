// The whole-board part of `m2mlat setup` (board.hpp).
#include "m2mlat/setup/board.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/chrony.hpp"
#include "m2mlat/setup/env_file.hpp"
#include "m2mlat/setup/gpio.hpp"
#include "m2mlat/setup/irq.hpp"
#include "m2mlat/setup/pin_chrony.hpp"

namespace m2mlat::setup {

sync::SyncRole default_sync_role(std::string_view board_role) {
  return agent_role(board_role) == "cause" ? sync::SyncRole::reference : sync::SyncRole::peer;
}

Plan plan_board(BoardSetup setup, const BoardState& state) {
  Plan plan;
  plan.part = fmt::format("board ({} board {}, {})", setup.agent.role, setup.agent.node,
                          sync::to_string(setup.chrony.mode));
  plan.append(plan_gpio(GpioSetup{setup.users}, state.etc_group));

  setup.chrony.role =
      setup.sync_role.empty() ? default_sync_role(setup.agent.role) : sync::parse_sync_role(setup.sync_role);
  plan.steps.push_back(chrony_conf_step(setup.chrony, setup.chrony_conf));
  plan.steps.push_back(command_step({"systemctl", "restart", "chrony"}, "chronyd reads its new configuration",
                                    setup.chrony_conf));
  if (setup.chrony_core >= 0) plan.append(plan_pin_chrony(setup.chrony_core));

  // The agent's configuration; its env keys and the IRQ's go into one env file step.
  Plan agent = plan_agent(setup.agent, state.env);
  EnvKeys keys = agent_env_keys(setup.agent);
  Plan irq;
  if (setup.irq_core >= 0) {
    const IrqSetup irq_setup{setup.agent.chip, setup.agent.line, setup.agent.channel, setup.irq_core, {}};
    irq = plan_irq(irq_setup, state.interrupts, {});
    const auto more = irq_env_keys(irq_setup);
    keys.insert(keys.end(), more.begin(), more.end());
    irq.notes.clear();  // plan_irq's notes are about a missing --node; here the env file keeps it
    if (irq.steps.empty())
      irq.notes.push_back(
          fmt::format("the {} line's IRQ is routed to CPU {} when the agent starts (its unit reads"
                      " M2MLAT_IRQ_CPU)",
                      setup.agent.channel, setup.irq_core));
  }
  const auto env = env_path(setup.agent.node);
  for (const auto& step : agent.steps)
    if (step.path != env) plan.steps.push_back(step);
  if (!keys.empty())
    plan.steps.push_back(file_step(env, merge_env(state.env, keys, agent_unit(setup.agent.node)),
                                   setup.irq_core >= 0
                                       ? "the agent's options, and its IRQ's core at each start"
                                       : "where the agent listens and its options"));
  plan.append(irq);
  plan.notes.insert(plan.notes.end(), agent.notes.begin(), agent.notes.end());
  plan.notes.push_back("then: `m2mlat doctor` and `m2mlat clock` on this board (docs/field-guide.md)");
  return plan;
}

}  // namespace m2mlat::setup
