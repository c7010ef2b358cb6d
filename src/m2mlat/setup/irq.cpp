// The IRQ affinity part of `m2mlat setup` (irq.hpp).
#include "m2mlat/setup/irq.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/rt/irq.hpp"
#include "m2mlat/setup/names.hpp"

namespace m2mlat::setup {

namespace {

// The line's offset: the line itself when numeric, or the digits a name ends in (GPIO16 -> 16).
std::optional<int> line_offset(std::string_view line) {
  std::size_t start = line.size();
  while (start > 0 && line[start - 1] >= '0' && line[start - 1] <= '9') --start;
  int offset = 0;
  if (start == line.size() || line.size() - start > 5 || !core::parse_integer(line.substr(start), offset))
    return std::nullopt;
  return offset;
}

// The chip's name as a word of /proc/interrupts: "pinctrl-rp1", "gpiochip4" (from /dev/gpiochip4).
std::string chip_word(std::string_view chip) {
  const auto slash = chip.rfind('/');
  return std::string(slash == std::string_view::npos ? chip : chip.substr(slash + 1));
}

}  // namespace

std::string irq_consumer(std::string_view channel) { return fmt::format("m2mlat-{}", channel); }

std::vector<int> find_line_irqs(std::string_view interrupts, const IrqSetup& setup) {
  auto irqs = rt::find_irq_in_interrupts(interrupts, irq_consumer(setup.channel));
  if (!irqs.empty()) return irqs;
  const auto offset = line_offset(setup.line);
  if (!offset || setup.chip.empty()) return irqs;
  const auto chip = chip_word(setup.chip);
  for (const auto& row : rt::parse_interrupts(interrupts)) {
    // description: "<chip> <hwirq> <type> <actions...>"
    const auto& d = row.description;
    const auto first_end = d.find(' ');
    if (first_end == std::string::npos || d.substr(0, first_end) != chip) continue;
    const auto second_start = d.find_first_not_of(' ', first_end);
    if (second_start == std::string::npos) continue;
    const auto second_end = d.find(' ', second_start);
    if (d.substr(second_start, second_end - second_start) == std::to_string(*offset)) irqs.push_back(row.irq);
  }
  return irqs;
}

EnvKeys irq_env_keys(const IrqSetup& setup) {
  return {{"M2MLAT_IRQ_CPU", std::to_string(setup.core)}, {"M2MLAT_IRQ_NAME", irq_consumer(setup.channel)}};
}

Plan plan_irq(const IrqSetup& setup, std::string_view interrupts, std::string_view current_env) {
  if (setup.core < 0 || setup.core > 4095)
    throw core::Error(core::ErrorKind::usage, fmt::format("--core {}: use a CPU number 0..4095", setup.core));
  check_name("--channel", setup.channel);
  if (!setup.node.empty()) check_name("--node", setup.node);
  Plan plan;
  plan.part = "irq";
  const auto irqs = find_line_irqs(interrupts, setup);
  for (int irq : irqs)
    plan.steps.push_back(
        file_step(fmt::format("/proc/irq/{}/smp_affinity_list", irq), fmt::format("{}\n", setup.core),
                  fmt::format("IRQ {} of {} line {} to CPU {}", irq, setup.chip, setup.line, setup.core)));
  for (auto& step : plan.steps) step.in_place = true;
  if (irqs.empty())
    plan.notes.push_back(fmt::format(
        "no interrupt named '{}' (nor a '{} {}' row) in /proc/interrupts: the line is not held by a recorder "
        "now;"
        " {}",
        irq_consumer(setup.channel), setup.chip, setup.line,
        setup.node.empty() ? "start the agent and run this again, or give --node to route it at each start"
                           : "the agent's unit routes it when it starts"));
  if (!setup.node.empty()) {
    const auto path = env_path(setup.node);
    plan.steps.push_back(file_step(path,
                                   merge_env(current_env, irq_env_keys(setup), "m2mlat-agent@" + setup.node),
                                   "the agent unit routes the IRQ at each start (packaging/irq-affinity)"));
  } else {
    plan.notes.push_back(
        "the routing lasts until the line is released or the board restarts; --node NAME keeps it"
        " for the agent m2mlat-agent@NAME");
  }
  return plan;
}

}  // namespace m2mlat::setup
