// `m2mlat setup pin-chrony`: keeps chronyd on one core (a systemd drop-in with CPUAffinity=, the text
// of sync::chrony_cpu_dropin), away from the core that takes the GPIO interrupt and runs the
// capture thread; systemd is reloaded and chrony restarted when the drop-in changed.
#pragma once

#include "m2mlat/setup/plan.hpp"

namespace m2mlat::setup {

Plan plan_pin_chrony(int core);

}  // namespace m2mlat::setup
