// The parts of `m2mlat setup` (chrony, gpio, irq, pin-chrony, agent, board): their options, for the
// table in cmd_setup.cpp. The parts themselves are plans in src/m2mlat/setup/, applied by apply.hpp.
#pragma once

#include "m2mlat/cli/command.hpp"

namespace m2mlat::cli {

Runner attach_setup_chrony(CLI::App& sub);
Runner attach_setup_gpio(CLI::App& sub);
Runner attach_setup_irq(CLI::App& sub);
Runner attach_setup_pin_chrony(CLI::App& sub);
Runner attach_setup_agent(CLI::App& sub);
Runner attach_setup_board(CLI::App& sub);

}  // namespace m2mlat::cli
