// `m2mlat setup chrony`: chrony.conf for a synchronisation mode (the text of sync::chrony_config) at
// a chosen path and, with a CPU, the systemd drop-in that keeps chronyd on it (the text of
// sync::chrony_cpu_dropin), as a plan like every other part, so that it is announced, backed up
// and written by apply.hpp. It runs no command: chronyd is checked and restarted by the user (the
// plan's note says how), which also lets tests write configurations for chronyd instances of their
// own. `setup board` takes its chrony.conf step from here.
#pragma once

#include <string>

#include "m2mlat/setup/plan.hpp"
#include "m2mlat/sync/chrony_config.hpp"

namespace m2mlat::setup {

// The file step of chrony.conf for options.mode (and role) at `path`.
Step chrony_conf_step(const sync::ChronyConfigOptions& options, const std::string& path);

// chrony.conf at `conf_path`; with cpu >= 0 also the drop-in at `dropin_path`. Throws
// core::Error(usage) for options sync::chrony_config refuses.
Plan plan_chrony(const sync::ChronyConfigOptions& options, const std::string& conf_path, int cpu,
                 const std::string& dropin_path);

}  // namespace m2mlat::setup
