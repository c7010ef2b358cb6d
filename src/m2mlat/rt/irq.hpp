// The interrupt of a captured line, and where it runs. The kernel takes the edge's timestamp in the
// hard IRQ handler, on whichever core the interrupt is routed to; pinning it to a chosen core (away
// from the busy ones) keeps that handler prompt. A GPIO line request's IRQ is named after the
// request's consumer label in /proc/interrupts, which is how it is found.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/rt/outcome.hpp"

namespace m2mlat::rt {

// One numbered line of /proc/interrupts.
struct InterruptLine {
  int irq = 0;
  std::vector<std::uint64_t> counts;  // interrupts served per CPU column
  std::string description;            // the rest: chip, hardware irq, type, actions
  std::vector<std::string> actions;   // the handlers' names (the last words, split at ", ")
};

// Parses the text of /proc/interrupts; rows that are not numbered IRQs (NMI, LOC, ERR...) are left out.
std::vector<InterruptLine> parse_interrupts(std::string_view text);
// The IRQs whose action is named `consumer` (a line request's consumer label), in file order.
std::vector<int> find_irq_in_interrupts(std::string_view interrupts_text, std::string_view consumer);
// The same, reading <proc_root>/interrupts.
std::vector<int> find_irq_by_consumer(std::string_view consumer, const std::string& proc_root = "/proc");

// Routes IRQ `irq` to CPU `cpu` by writing <proc_root>/irq/<irq>/smp_affinity_list (needs root).
Outcome pin_irq(int irq, int cpu, const std::string& proc_root = "/proc");
// The CPU list an IRQ is routed to (effective_affinity_list if the kernel has it, else
// smp_affinity_list), e.g. "0-3"; empty if unreadable.
std::optional<std::string> irq_affinity(int irq, const std::string& proc_root = "/proc");

}  // namespace m2mlat::rt
