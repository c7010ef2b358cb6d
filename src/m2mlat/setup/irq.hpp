// `m2mlat setup irq`: routes the interrupt of a captured GPIO line to one core, now and at every
// start of the agent.
//   now:        writes the core to /proc/irq/<N>/smp_affinity_list (root). The kernel creates a
//               line's IRQ action when a program requests the line for edges, named after the
//               request's consumer label ("m2mlat-<channel>", capture/gpio_source), so the IRQ is
//               found in /proc/interrupts by that name while the agent (or a recorder) holds the line;
//               or, for a numeric line, by the GPIO chip's row for that hardware line ("<chip> <line>").
//   persistent: M2MLAT_IRQ_CPU and M2MLAT_IRQ_NAME in /etc/m2mlat/<node>.env. The agent runs
//               unprivileged and cannot write /proc/irq, so the agent's own [rt] irq_cpu key is not
//               used: the unit's root helper (packaging/irq-affinity, ExecStartPost=+) reads these keys
//               and routes the IRQ each time the agent starts.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/setup/env_file.hpp"
#include "m2mlat/setup/plan.hpp"

namespace m2mlat::setup {

struct IrqSetup {
  std::string chip;               // the line's chip: name, label or path (for the chip-row lookup)
  std::string line;               // its line: offset or name (GPIO16)
  std::string channel = "wheel";  // the channel name in the agent's configuration
  int core = -1;                  // the CPU to route to
  std::string node;               // the agent instance whose env file keeps the setting; "" = now only
};

// "m2mlat-<channel>": the consumer label, the IRQ's action name in /proc/interrupts.
std::string irq_consumer(std::string_view channel);
// The IRQs of the line in the text of /proc/interrupts: those whose action is the consumer label,
// else (numeric line, or a name ending in its offset like GPIO16) the rows "<chip> <offset>".
std::vector<int> find_line_irqs(std::string_view interrupts, const IrqSetup& setup);
// The environment keys that keep the routing (M2MLAT_IRQ_CPU, M2MLAT_IRQ_NAME).
EnvKeys irq_env_keys(const IrqSetup& setup);

// The plan, given /proc/interrupts and the node's current env file ("" if none): one in-place write
// of /proc/irq/<N>/smp_affinity_list per IRQ found, and the env keys when a node is named.
Plan plan_irq(const IrqSetup& setup, std::string_view interrupts, std::string_view current_env);

}  // namespace m2mlat::setup
