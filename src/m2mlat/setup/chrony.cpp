// The chrony part of `m2mlat setup` (chrony.hpp).
#include "m2mlat/setup/chrony.hpp"

#include <fmt/format.h>

namespace m2mlat::setup {

Step chrony_conf_step(const sync::ChronyConfigOptions& options, const std::string& path) {
  return file_step(path, sync::chrony_config(options),
                   fmt::format("chrony for the {} mode{}", sync::to_string(options.mode),
                               options.mode == sync::SyncMode::co_referenced
                                   ? fmt::format(" ({})", sync::to_string(options.role))
                                   : ""));
}

Plan plan_chrony(const sync::ChronyConfigOptions& options, const std::string& conf_path, int cpu,
                 const std::string& dropin_path) {
  Plan plan;
  plan.part = "chrony";
  plan.steps.push_back(chrony_conf_step(options, conf_path));
  if (cpu >= 0)
    plan.steps.push_back(
        file_step(dropin_path, sync::chrony_cpu_dropin(cpu), fmt::format("chronyd runs on CPU {} only", cpu)));
  plan.notes.push_back(fmt::format(
      "check it with `chronyd -p -f {}`, restart chronyd{}, and watch `m2mlat clock --watch`", conf_path,
      cpu >= 0 ? " (systemctl daemon-reload && systemctl restart chrony)" : " (systemctl restart chrony)"));
  return plan;
}

}  // namespace m2mlat::setup
