// The chronyd CPU pinning part of `m2mlat setup` (pin_chrony.hpp).
#include "m2mlat/setup/pin_chrony.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sync/chrony_config.hpp"

namespace m2mlat::setup {

Plan plan_pin_chrony(int core) {
  if (core < 0 || core > 4095)
    throw core::Error(core::ErrorKind::usage, fmt::format("--core {}: use a CPU number 0..4095", core));
  Plan plan;
  plan.part = "pin-chrony";
  const std::string path(sync::kChronyDropinPath);
  plan.steps.push_back(
      file_step(path, sync::chrony_cpu_dropin(core), fmt::format("chronyd runs on CPU {} only", core)));
  plan.steps.push_back(command_step({"systemctl", "daemon-reload"}, "systemd reads the drop-in", path));
  plan.steps.push_back(command_step({"systemctl", "restart", "chrony"}, "chronyd moves to its core", path));
  return plan;
}

}  // namespace m2mlat::setup
